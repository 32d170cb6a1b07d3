//! The cadre command line.
fn main() {}
