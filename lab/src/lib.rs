//! meshfree-lab: the laboratory. `validate` (one case per file, against experiments and
//! analytic solutions), `stability` (maps of stable / inaccurate / failed runs over two swept
//! parameters), `chart` (error against wall time, the Pareto front) and the plots they draw;
//! `lbm`, a small lattice Boltzmann solver, the grid-based reference for the vortex streets.
//! Every case steps through the solver's one stepping path, `meshfree_core::step`.
pub mod chart;
pub mod lbm;
pub mod plot;
pub mod stability;
pub mod validate;
