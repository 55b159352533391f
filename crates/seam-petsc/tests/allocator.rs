//! A process that links PETSc gives freed memory back to the system.
//!
//! Debian's libsuperlu_dist, which PETSc links, switches glibc's mmap and heap
//! trimming off in its constructor; seam's PETSc layer switches them on again
//! in one of its own (`src/shim.c`), or a solve's peak memory would be the sum
//! of its phases. Run on the main thread (`harness = false`), whose heap is the
//! one those settings govern: a touched 512 MB block must go back at drop.

fn resident_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("Linux's /proc");
    let line = status.lines().find(|l| l.starts_with("VmRSS:")).expect("a VmRSS line");
    line.split_whitespace().nth(1).and_then(|kb| kb.parse::<f64>().ok()).expect("kB") / 1024.0
}

fn main() {
    seam_petsc::initialize("").expect("PETSc starts");
    let block = std::hint::black_box(vec![1u8; 512 << 20]);
    let held = resident_mb();
    drop(block);
    let freed = held - resident_mb();
    seam_petsc::finalize();
    assert!(freed > 384.0, "only {freed:.0} MB of a freed 512 MB block went back to the system");
    println!("allocator: {freed:.0} MB of a freed 512 MB block went back to the system");
}
