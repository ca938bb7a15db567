//! Output frames off the stepping path (`Solver::capture`, `crate::frame`).
//!
//! At an output the solver's stream copies the chosen fields of the current arrays into a
//! staging set on the device (device-to-device, well under a millisecond for millions of
//! particles) and records an event; the solver steps on at once. The frame's
//! `PendingFrame::wait`, called by the run's writer thread, makes a second stream wait for
//! that event, downloads the staging set into host memory there and converts it to
//! `FrameData` (three-component vectors, six-component stress), then gives the staging set
//! back. Two staging sets at most: a third capture while two frames are still being
//! downloaded waits for one (back-pressure, which the run reports as output wait).

use std::sync::{Arc, Condvar, Mutex};

use cudarc::driver::{CudaContext, CudaEvent, CudaSlice, CudaStream, DriverError};

use super::buffers::{nsym, sym_slots, vstride, Buffers, VEL_STRIDE};
use crate::dim::Dim;
use crate::frame::{Field, Fields, FrameData, PendingFrame};

/// Staging sets in flight at most.
const SETS: usize = 2;

/// Device copies of the captured fields (allocated for the fields and size at hand).
struct Staging {
    n: usize,
    fields: Fields,
    pos: Option<CudaSlice<f32>>,
    vel: Option<CudaSlice<f32>>,
    rho: Option<CudaSlice<f32>>,
    p: Option<CudaSlice<f32>>,
    kind: Option<CudaSlice<u8>>,
    id: Option<CudaSlice<u32>>,
    group: Option<CudaSlice<u32>>,
    stress: Option<CudaSlice<f32>>,
}

/// The free staging sets and how many exist, shared with the frames in flight.
#[derive(Default)]
struct Pool {
    free: Vec<Staging>,
    allocated: usize,
}

/// The solver's side: the download stream and the staging pool.
pub struct Capturer {
    copy: Arc<CudaStream>,
    pool: Arc<(Mutex<Pool>, Condvar)>,
}

impl Capturer {
    pub fn new(ctx: &Arc<CudaContext>) -> Result<Capturer, DriverError> {
        Ok(Capturer {
            copy: ctx.new_stream()?,
            pool: Arc::default(),
        })
    }

    /// Start a capture of `fields` of `buf`'s current arrays on `stream` (waits while two
    /// frames are still being downloaded).
    pub fn start<D: Dim>(
        &self,
        stream: &Arc<CudaStream>,
        buf: &Buffers,
        fields: Fields,
        step: u64,
        time: f64,
    ) -> Result<Box<dyn PendingFrame>, DriverError> {
        let n = buf.n;
        let has_stress = buf.cur.stress.is_some();
        let fields = if has_stress {
            fields
        } else {
            Fields::of(
                &fields
                    .list()
                    .into_iter()
                    .filter(|&f| f != Field::Stress)
                    .collect::<Vec<_>>(),
            )
        };
        let reuse = {
            let (lock, freed) = &*self.pool;
            let mut pool = lock.lock().expect("staging pool");
            while pool.free.is_empty() && pool.allocated >= SETS {
                pool = freed.wait(pool).expect("staging pool");
            }
            let found = pool.free.pop();
            if found.is_none() {
                pool.allocated += 1;
            }
            found
        };
        let mut set = match reuse {
            Some(s) if s.n == n && s.fields == fields => s,
            _ => match Staging::alloc::<D>(stream, n, fields) {
                Ok(s) => s,
                Err(e) => {
                    self.pool.0.lock().expect("staging pool").allocated -= 1;
                    return Err(e);
                }
            },
        };
        let c = &buf.cur;
        fn copy<T>(
            s: &Arc<CudaStream>,
            src: &CudaSlice<T>,
            dst: &mut Option<CudaSlice<T>>,
        ) -> Result<(), DriverError> {
            match dst {
                Some(d) => {
                    let len = d.len();
                    s.memcpy_dtod(&src.slice(..len), d)
                }
                None => Ok(()),
            }
        }
        copy(stream, &c.pos, &mut set.pos)?;
        copy(stream, &c.vel, &mut set.vel)?;
        copy(stream, &c.rho, &mut set.rho)?;
        copy(stream, &c.p, &mut set.p)?;
        copy(stream, &c.kind, &mut set.kind)?;
        copy(stream, &c.id, &mut set.id)?;
        copy(stream, &c.group, &mut set.group)?;
        if let Some(st) = &c.stress {
            copy(stream, st, &mut set.stress)?;
        }
        let copied = stream.record_event(None)?;
        Ok(Box::new(Pending::<D> {
            set: Some(set),
            copied,
            copy: self.copy.clone(),
            pool: self.pool.clone(),
            step,
            time,
            _d: std::marker::PhantomData,
        }))
    }
}

impl Staging {
    fn alloc<D: Dim>(
        s: &Arc<CudaStream>,
        n: usize,
        fields: Fields,
    ) -> Result<Staging, DriverError> {
        fn z<T: cudarc::driver::DeviceRepr + cudarc::driver::ValidAsZeroBits>(
            s: &Arc<CudaStream>,
            on: bool,
            len: usize,
        ) -> Result<Option<CudaSlice<T>>, DriverError> {
            if on {
                s.alloc_zeros::<T>(len.max(1)).map(Some)
            } else {
                Ok(None)
            }
        }
        let has = |f| fields.has(f);
        Ok(Staging {
            n,
            fields,
            pos: z(s, has(Field::Position), n * vstride::<D>())?,
            vel: z(s, has(Field::Velocity), n * VEL_STRIDE)?,
            rho: z(s, has(Field::Density), n)?,
            p: z(s, has(Field::Pressure), n)?,
            kind: z(s, has(Field::Kind), n)?,
            id: z(s, has(Field::Id), n)?,
            group: z(s, has(Field::Group), n)?,
            stress: z(s, has(Field::Stress), n * nsym::<D>())?,
        })
    }
}

/// A frame whose device copy is queued; `wait` downloads it.
struct Pending<D: Dim> {
    set: Option<Staging>,
    copied: CudaEvent,
    copy: Arc<CudaStream>,
    pool: Arc<(Mutex<Pool>, Condvar)>,
    step: u64,
    time: f64,
    _d: std::marker::PhantomData<fn() -> D>,
}

impl<D: Dim> Pending<D> {
    fn download(&self, set: &Staging) -> Result<FrameData, DriverError> {
        let s = &self.copy;
        s.wait(&self.copied)?;
        fn get<T: cudarc::driver::DeviceRepr>(
            s: &Arc<CudaStream>,
            d: &Option<CudaSlice<T>>,
        ) -> Result<Vec<T>, DriverError> {
            d.as_ref().map_or(Ok(Vec::new()), |d| s.clone_dtoh(d))
        }
        let (pos, vel, stress) = (get(s, &set.pos)?, get(s, &set.vel)?, get(s, &set.stress)?);
        let (mut rho, mut p, mut kind) = (get(s, &set.rho)?, get(s, &set.p)?, get(s, &set.kind)?);
        let (mut id, mut group) = (get(s, &set.id)?, get(s, &set.group)?);
        s.synchronize()?;
        let n = set.n;
        rho.truncate(n);
        p.truncate(n);
        kind.truncate(n);
        id.truncate(n);
        group.truncate(n);
        let vectors = |f: &[f32], stride: usize| -> Vec<[f32; 3]> {
            if f.is_empty() {
                return Vec::new();
            }
            (0..n)
                .map(|i| {
                    let mut a = [0.0f32; 3];
                    a[..D::D].copy_from_slice(&f[i * stride..i * stride + D::D]);
                    a
                })
                .collect()
        };
        let stress = if stress.is_empty() {
            Vec::new()
        } else {
            let slots = sym_slots::<D>();
            (0..n)
                .map(|i| {
                    let mut s6 = [0.0f32; 6];
                    for (k, &c) in slots.iter().enumerate() {
                        s6[c] = stress[k * n + i];
                    }
                    s6
                })
                .collect()
        };
        Ok(FrameData {
            step: self.step,
            time: self.time,
            len: n,
            position: vectors(&pos, vstride::<D>()),
            velocity: vectors(&vel, VEL_STRIDE),
            density: rho,
            pressure: p,
            kind,
            id,
            group,
            stress,
        })
    }
}

impl<D: Dim> PendingFrame for Pending<D> {
    fn wait(mut self: Box<Self>) -> Result<FrameData, String> {
        let set = self
            .set
            .take()
            .expect("a pending frame holds its staging set");
        let r = self.download(&set);
        let (lock, freed) = &*self.pool;
        lock.lock().expect("staging pool").free.push(set);
        freed.notify_one();
        r.map_err(|e| format!("downloading an output frame from the GPU failed: {e:?}"))
    }
}

impl<D: Dim> Drop for Pending<D> {
    /// A frame dropped unread gives its staging set back too.
    fn drop(&mut self) {
        if let Some(set) = self.set.take() {
            let (lock, freed) = &*self.pool;
            if let Ok(mut pool) = lock.lock() {
                pool.free.push(set);
            }
            freed.notify_one();
        }
    }
}
