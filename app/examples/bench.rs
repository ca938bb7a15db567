//! `cargo run --release --example bench -- [auto|cpu|cuda] [dims e.g. 2,3] [sizes e.g. 3000,30000]
//! [steps] [out_dir]`: the `meshfree::bench` library function without the CLI.
use meshfree::bench::{bench, BenchOptions};
use meshfree_core::backend::BackendChoice;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let mut o = BenchOptions::default();
    if let Some(b) = a.first() {
        o.backend = match b.as_str() {
            "cpu" => BackendChoice::Cpu,
            "cuda" => BackendChoice::Cuda,
            _ => BackendChoice::Auto,
        };
    }
    if let Some(d) = a.get(1) {
        o.dims = d.split(',').map(|x| x.parse().expect("dims")).collect();
    }
    if let Some(s) = a.get(2) {
        o.sizes = s
            .split(',')
            .map(|x| x.parse::<f64>().expect("sizes") as usize)
            .collect();
    }
    if let Some(s) = a.get(3) {
        o.steps = s.parse().expect("steps");
    }
    o.count_neighbours = std::env::var("MESHFREE_BENCH_NEIGHBOURS").map_or(true, |v| v != "0");
    let out = a.get(4).map(std::path::PathBuf::from);
    if let Err(e) = bench(&o, out.as_deref()) {
        eprintln!("bench failed: {e}");
        std::process::exit(1);
    }
}
