//! meshfree-lab: the laboratory. `validate` (one case per file, against experiments and
//! analytic solutions), `stability` (maps of stable / inaccurate / failed runs over two swept
//! parameters), `chart` (error against wall time, the Pareto front) and the plots they draw;
//! `lbm`, a small lattice Boltzmann solver, the grid-based reference for the vortex streets.
//! Every case steps through the solver's one stepping path, `meshfree_core::solver::step`.
/// `eprintln!` for the lab's progress notes that never panics: a closed pipe or a hung-up
/// terminal on standard error must not stop a validation or a sweep (issue #52).
#[macro_export]
macro_rules! note {
    ($($a:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($a)*);
    }};
}

pub mod chart;
pub mod lbm;
pub mod plot;
pub mod stability;
pub mod validate;
