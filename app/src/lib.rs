//! The `meshfree` binary's library: the command line, the run driver and its output,
//! monitors' and probes' files, analyses of particle sets, benchmarks and comparisons. The solver is
//! `meshfree_core`; validation, stability maps and charts are `meshfree_lab`.
pub mod analysis;
pub mod bad_input;
pub mod bench;
pub mod cli;
pub mod compare;
pub mod docs;
pub mod interrupt;
pub mod monitors;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod nearest;
pub mod output;
pub mod paper_bench;
pub mod peers_bench;
pub mod probes;
pub mod resume;
pub mod run;
pub mod run_error;
pub mod term;
