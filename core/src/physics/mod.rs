//! The physics every backend shares: dimensions (`dim`), the smoothing kernels (`kernel`),
//! one particle (`particle`) and the struct-of-arrays state (`state`), the parameter struct
//! the kernels read (`params`), a driven object's prescribed motion (`motion`), a floating rigid body (`body`), the ghost nodes of modified dynamic walls (`mdbc`), open boundaries' buffers (`open`), the pair terms of the equations (`pairs`) and the
//! total-Lagrangian solid's reference configuration (`tlsph`).

pub mod body;
pub mod dim;
pub mod kernel;
pub mod mdbc;
pub mod motion;
pub mod open;
pub mod pairs;
pub mod params;
pub mod particle;
pub mod state;
pub mod tlsph;
