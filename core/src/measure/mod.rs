//! What a run measures besides its frames: force monitors on walls and bodies (`monitor`),
//! probes and free-surface gauges (`probe`) and the void metric of a confined flow (`voids`).

pub mod monitor;
pub mod probe;
pub mod voids;
