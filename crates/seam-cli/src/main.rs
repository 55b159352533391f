//! The `seam` command-line tool (being written).
fn main() {}
