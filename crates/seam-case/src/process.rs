//! Figures of this process, from Linux's `/proc/self/status`.

/// A memory figure of this process in bytes: `key` is `VmHWM` (peak
/// resident memory) or `VmRSS` (resident now); `None` where
/// `/proc/self/status` is not readable (not Linux) or has no such line.
pub fn memory_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find_map(|l| l.strip_prefix(key)?.strip_prefix(':'))?;
    let kb: u64 = line.trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kb * 1024)
}

/// The peak resident memory of this process in MB (10⁶ bytes), as
/// `summary.json` reports it.
pub fn peak_memory_mb() -> Option<f64> {
    memory_bytes("VmHWM").map(|b| b as f64 / 1e6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_is_at_least_the_resident_memory() {
        if !cfg!(target_os = "linux") {
            return;
        }
        let rss = memory_bytes("VmRSS").unwrap();
        let peak = memory_bytes("VmHWM").unwrap();
        assert!(rss > 1 << 20 && peak >= rss, "{rss} {peak}");
        assert!(memory_bytes("NoSuchKey").is_none());
    }
}
