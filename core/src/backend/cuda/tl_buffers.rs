//! The total-Lagrangian bodies' arrays on the device (`cuda/tlsph.cu`, launched by
//! `launch/tlsph.rs`): their reference configuration, uploaded once, and what the stages keep
//! per solid particle, in the layout of `buffers.rs`. Twin: `backend/cpu/tlsph.rs`.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, DriverError};

use super::buffers::{flat_v, unflat_v, vstride, Alloc};
use crate::physics::dim::Dim;

/// The total-Lagrangian bodies on the device (`cuda/tlsph.cu`), in solid space (index a =
/// the solid particle's rank by id, `crate::physics::tlsph::Reference`): the reference configuration,
/// uploaded once, and what the stages keep per solid particle. Not reordered by the grid;
/// `slot` maps solid space onto the storage after each reorder (`sph_tl_slots`).
pub struct TlBuffers {
    /// Solid particles.
    pub n_solid: usize,
    /// Particle id -> solid index (`tlsph::NONE` for other particles).
    pub index: CudaSlice<u32>,
    /// Its length (largest id + 1).
    pub n_index: usize,
    /// [L] X0, float2 (2D) / float4 (3D, w = 0).
    pub x0: CudaSlice<f32>,
    /// [L^d] V0.
    pub vol: CudaSlice<f32>,
    /// [L] C, the reference gradient's second-order correction (`tlsph::gradient`): Q
    /// columns of D floats per solid (`corr_columns`).
    pub corr: CudaSlice<f32>,
    /// [-] omega / V0, the strain energy's quadrature weight (`tlsph::quadrature`).
    pub quad: CudaSlice<f32>,
    /// CSR of the reference neighbours (solid indices).
    pub start: CudaSlice<u32>,
    pub nbr: CudaSlice<u32>,
    /// [L^-d] F, the clamp's face term (`tlsph::Reference::face`): Q floats per solid.
    pub face: CudaSlice<f32>,
    /// The clamp particle whose displacement the face takes (`tlsph::NONE`: no face).
    pub face_clamp: CudaSlice<u32>,
    /// CSR of the face points within each solid's support (`tlsph::Reference::faces_of`):
    /// offsets, and D + 1 + Q floats per point (`tlsph::FacePair`: X0_m [L], V_m [L^d], then
    /// the fit's value weights r_am [-]).
    pub face_start: CudaSlice<u32>,
    pub face_pts: CudaSlice<f32>,
    /// Solid index -> storage slot (`tlsph::NONE`: removed).
    pub slot: CudaSlice<u32>,
    /// [L] u = x - X0, as x0.
    pub disp: CudaSlice<f32>,
    /// [-] H = F - I, row-major D x D.
    pub grad: CudaSlice<f32>,
    /// [M L^-d L^2 T^-2 L] (omega / V0) P C, as corr.
    pub pk1_corr: CudaSlice<f32>,
    /// Bytes allocated for the above.
    pub bytes: usize,
}

/// Corrections -> Q = `basis_len(D)` columns of D floats each, column after column.
fn corr_columns<D: Dim>(c: &[crate::physics::tlsph::Corr<D>]) -> Vec<f32> {
    let q = crate::physics::tlsph::gradient::basis_len(D::D);
    c.iter()
        .flat_map(|x| {
            x[..q]
                .iter()
                .flat_map(|&v| (0..D::D).map(move |k| D::comp(v, k)))
        })
        .collect()
}

impl TlBuffers {
    /// Allocate and upload the reference configuration `r` with zero displacement, every
    /// slot `NONE` (the first `sph_tl_slots` fills them).
    pub fn new<D: Dim>(
        s: &Arc<CudaStream>,
        r: &crate::physics::tlsph::Reference<D>,
    ) -> Result<TlBuffers, DriverError> {
        let n = r.len();
        let vs = vstride::<D>();
        let dd = D::D * D::D;
        let dq = D::D * crate::physics::tlsph::gradient::basis_len(D::D);
        let mut a = Alloc { s, bytes: 0 };
        let mut t = TlBuffers {
            n_solid: n,
            index: a.z(r.index_of_id.len())?,
            n_index: r.index_of_id.len(),
            x0: a.z(n * vs)?,
            vol: a.z(n)?,
            corr: a.z(n * dq)?,
            quad: a.z(n)?,
            start: a.z(n + 1)?,
            nbr: a.z(r.nbr.len())?,
            face: a.z(n * dq / D::D)?,
            face_clamp: a.z(n)?,
            face_start: a.z(n + 1)?,
            face_pts: a.z(r.face_pts.len().max(1) * (D::D + 1 + dq / D::D))?,
            slot: a.z(n)?,
            disp: a.z(n * vs)?,
            grad: a.z(n * dd)?,
            pk1_corr: a.z(n * dq)?,
            bytes: 0,
        };
        t.bytes = a.bytes;
        if !r.index_of_id.is_empty() {
            s.memcpy_htod(&r.index_of_id, &mut t.index)?;
        }
        if n > 0 {
            s.memcpy_htod(&flat_v::<D>(&r.x0, |_| 0.0), &mut t.x0)?;
            s.memcpy_htod(&r.vol, &mut t.vol)?;
            s.memcpy_htod(&corr_columns::<D>(&r.corr), &mut t.corr)?;
            s.memcpy_htod(&r.quad, &mut t.quad)?;
            let q = dq / D::D;
            let face: Vec<f32> = r.face.iter().flat_map(|f| f[..q].iter().copied()).collect();
            s.memcpy_htod(&face, &mut t.face)?;
            s.memcpy_htod(&r.face_clamp, &mut t.face_clamp)?;
            s.memcpy_htod(&r.face_start, &mut t.face_start)?;
        }
        if !r.face_pts.is_empty() {
            let q = dq / D::D;
            let pts: Vec<f32> = r
                .face_pts
                .iter()
                .flat_map(|m| {
                    (0..D::D)
                        .map(move |k| D::comp(m.x0, k))
                        .chain([m.vol])
                        .chain(m.fit[..q].iter().copied())
                })
                .collect();
            s.memcpy_htod(&pts, &mut t.face_pts)?;
        }
        s.memcpy_htod(&r.start, &mut t.start)?;
        if !r.nbr.is_empty() {
            s.memcpy_htod(&r.nbr, &mut t.nbr)?;
        }
        t.clear_slots(s)?;
        Ok(t)
    }

    /// Every slot `NONE` (before the map of a storage whose set of solids changed).
    pub fn clear_slots(&mut self, s: &Arc<CudaStream>) -> Result<(), DriverError> {
        if self.n_solid > 0 {
            s.memcpy_htod(
                &vec![crate::physics::tlsph::NONE; self.n_solid],
                &mut self.slot,
            )?;
        }
        Ok(())
    }

    /// Overwrite the displacements u in solid space (`n_solid` of them).
    pub fn write_disp<D: Dim>(
        &mut self,
        s: &Arc<CudaStream>,
        disp: &[D::V],
    ) -> Result<(), DriverError> {
        assert_eq!(disp.len(), self.n_solid, "write_disp: another solid count");
        if self.n_solid > 0 {
            s.memcpy_htod(&flat_v::<D>(disp, |_| 0.0), &mut self.disp)?;
        }
        Ok(())
    }

    /// The displacements u in solid space (read back).
    pub fn read_disp<D: Dim>(&self, s: &Arc<CudaStream>) -> Result<Vec<D::V>, DriverError> {
        Ok(unflat_v::<D>(&s.clone_dtoh(&self.disp)?, self.n_solid))
    }
}
