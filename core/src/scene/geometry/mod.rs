//! Surfaces from files and point lists (issue #53): the `mesh` (3D) and `polygon` (2D) shapes
//! of walls, solids and fluid blocks (`format::Outline`). A surface is read once, when the
//! scene is (`load`), moved into place (scale, rotate, translate), checked (a volume must be
//! closed up to small holes) and oriented (outward), and then answers the generator's
//! questions: which lattice points are inside (the generalised winding number, `winding.rs`,
//! robust to small holes and self-intersections), how far a point is from the surface and
//! where its closest point is (parry's bounding-volume trees: `parry3d-f64`'s `TriMesh`, and
//! `parry2d-f64`'s `Polyline` for a polygon). Lengths are the scene's \[L\].
//!
//! `base.rs`: where the files are; `read.rs`: the file formats; `load.rs`: reading, placing
//! and checking one surface; `surface.rs`: a surface in place and its queries (inside,
//! closest point, lattice); `winding.rs`: the fast winding number; `topology.rs`: a
//! surface's edges (holes); `objects.rs`: the scene's surfaces; `copies.rs`: a run's copies
//! of their files; `pack.rs`: body-fitted particles.

mod base;
mod copies;
mod load;
mod objects;
pub mod pack;
pub mod read;
pub mod surface;
mod topology;
mod winding;

pub use base::{base_of, Base, ASSETS};
pub use copies::SurfaceCopy;
pub(in crate::scene) use objects::{check, load_all};
pub use objects::{surfaces, Placed};
pub use surface::{Info, Loaded, Pick, Surface, MAX_HOLE};
pub use topology::Topology;
