//! Prints a generated benchmark dataset: `cargo run --release --example generate_chain -- N [pendulum|hanging]`.
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    match std::env::args().nth(2).as_deref() {
        Some("pendulum") => print!("{}", linkage_solve::generate::pendulum_chain(n)),
        Some("hanging") => print!("{}", linkage_solve::generate::hanging_chain(n)),
        _ => print!("{}", linkage_solve::generate::parallelogram_chain(n, 60.0)),
    }
}
