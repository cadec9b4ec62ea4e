//! Runs the `eigs` comparison without the `compare` harness:
//! `cargo run --release -p dirac-bench --example eigs -- LEVEL K REPEATS [case,case,…]`.

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let level = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5);
    let k = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(60);
    let repeats = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let cases: Vec<&str> = match args.get(4) {
        Some(list) => list.split(',').collect(),
        None => dirac_bench::eigs::EIGS_CASES.to_vec(),
    };
    println!(
        "{}",
        dirac_bench::eigs::compare_eigs_cases(level, k, repeats, &cases)
    );
}
