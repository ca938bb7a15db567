//! What a run measures besides its frames: force monitors on walls and bodies (`monitor`),
//! probes and free-surface gauges (`probe`), the void metric of a confined flow (`voids`),
//! and, after a run, the incident and reflected waves at its gauges (`reflection`).

pub mod monitor;
pub mod probe;
pub mod reflection;
pub mod sea_state;
pub mod voids;
