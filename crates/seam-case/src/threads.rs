//! How many worker threads a run may start: a sane multiple of the cores.
//!
//! A thread pool spawns its threads up front; `--threads 100000` would spend
//! minutes creating threads before any work (and can exhaust the process's
//! limits). Beyond a few threads per core nothing runs faster.

/// The most worker threads per core a run may ask for.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// The cores of this machine as the standard library sees them (1 if unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The most worker threads a run may ask for on this machine.
pub fn max_threads() -> usize {
    MAX_THREADS_PER_CORE * cores()
}

/// `requested` if 1 ≤ `requested` ≤ [`max_threads`].
///
/// # Errors
/// A one-line reason, for example "100000 worker threads are more than 4 per
/// core (this machine has 2 cores: at most 8)".
pub fn check_threads(requested: usize) -> Result<usize, String> {
    if requested == 0 {
        return Err("the number of worker threads must be at least 1".into());
    }
    let (cores, max) = (cores(), max_threads());
    if requested > max {
        return Err(format!(
            "{requested} worker threads are more than {MAX_THREADS_PER_CORE} per core (this machine has {cores} \
             core{}: at most {max})",
            if cores == 1 { "" } else { "s" }
        ));
    }
    Ok(requested)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts_are_checked_against_the_cores() {
        assert_eq!(check_threads(1), Ok(1));
        assert_eq!(check_threads(max_threads()), Ok(max_threads()));
        assert!(check_threads(0).unwrap_err().contains("at least 1"));
        let err = check_threads(100_000).unwrap_err();
        assert!(err.starts_with("100000 worker threads are more than 4 per core"), "{err}");
        assert!(err.ends_with(&format!("at most {})", max_threads())), "{err}");
    }
}
