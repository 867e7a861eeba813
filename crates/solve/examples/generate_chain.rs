//! Prints a generated benchmark dataset: `cargo run --release --example generate_chain -- N [pendulum]`.
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    if std::env::args().nth(2).as_deref() == Some("pendulum") {
        print!("{}", linkage_solve::generate::pendulum_chain(n));
    } else {
        print!("{}", linkage_solve::generate::parallelogram_chain(n, 60.0));
    }
}
