//! Output frames off the stepping path (`Readback::capture`, `crate::solver::frame`).
//!
//! At an output the solver's stream copies the chosen fields of the current arrays into a
//! staging set on the device (device-to-device, well under a millisecond for millions of
//! particles) and records an event; the solver steps on at once. The frame's
//! `PendingFrame::wait`, called by the run's writer thread, makes a second stream wait for
//! that event, downloads the staging set there into the set's pinned host buffers (a
//! pageable download ran at about 0.9 GB/s on the H100's host: 0.8 s for a 13.5 M-particle
//! frame) and converts it to
//! `FrameData` (three-component vectors, six-component stress), then gives the staging set
//! back. Two staging sets at most: a third capture while two frames are still being
//! downloaded waits for one (back-pressure, which the run reports as output wait).

use std::sync::{Arc, Condvar, Mutex};

use cudarc::driver::{
    CudaContext, CudaEvent, CudaSlice, CudaStream, DeviceRepr, DriverError, PinnedHostSlice,
    ValidAsZeroBits,
};

use super::buffers::{nsym, sym_slots, vstride, Buffers, VEL_STRIDE};
use crate::physics::dim::Dim;
use crate::solver::frame::{Field, Fields, FrameData, PendingFrame};

/// Staging sets in flight at most.
const SETS: usize = 2;

/// One captured array: its device copy and the pinned host buffer it is downloaded into.
struct Lane<T> {
    dev: CudaSlice<T>,
    host: PinnedHostSlice<T>,
}

/// Device copies of the captured fields and their host buffers (allocated for the fields
/// and size at hand).
struct Staging {
    n: usize,
    fields: Fields,
    pos: Option<Lane<f32>>,
    vel: Option<Lane<f32>>,
    rho: Option<Lane<f32>>,
    p: Option<Lane<f32>>,
    kind: Option<Lane<u8>>,
    id: Option<Lane<u32>>,
    group: Option<Lane<u32>>,
    stress: Option<Lane<f32>>,
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
            fields.without(Field::Stress)
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
            dst: &mut Option<Lane<T>>,
        ) -> Result<(), DriverError> {
            match dst {
                Some(d) => {
                    let len = d.dev.len();
                    s.memcpy_dtod(&src.slice(..len), &mut d.dev)
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
        fn lane<T: DeviceRepr + ValidAsZeroBits>(
            s: &Arc<CudaStream>,
            on: bool,
            len: usize,
        ) -> Result<Option<Lane<T>>, DriverError> {
            if !on {
                return Ok(None);
            }
            let len = len.max(1);
            // SAFETY: the host buffer is only read after a download has filled it. Flags 0:
            // cached pinned memory (write-combined memory is slow to read on the host).
            let host = unsafe { s.context().alloc_pinned_with_flags::<T>(len, 0)? };
            Ok(Some(Lane {
                dev: s.alloc_zeros::<T>(len)?,
                host,
            }))
        }
        let has = |f| fields.has(f);
        Ok(Staging {
            n,
            fields,
            pos: lane(s, has(Field::Position), n * vstride::<D>())?,
            vel: lane(s, has(Field::Velocity), n * VEL_STRIDE)?,
            rho: lane(s, has(Field::Density), n)?,
            p: lane(s, has(Field::Pressure), n)?,
            kind: lane(s, has(Field::Kind), n)?,
            id: lane(s, has(Field::Id), n)?,
            group: lane(s, has(Field::Group), n)?,
            stress: lane(s, has(Field::Stress), n * nsym::<D>())?,
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
    fn download(&self, set: &mut Staging) -> Result<FrameData, DriverError> {
        let s = &self.copy;
        s.wait(&self.copied)?;
        fn fetch<T: DeviceRepr>(
            s: &Arc<CudaStream>,
            l: &mut Option<Lane<T>>,
        ) -> Result<(), DriverError> {
            match l {
                Some(l) => s.memcpy_dtoh(&l.dev, &mut l.host),
                None => Ok(()),
            }
        }
        fetch(s, &mut set.pos)?;
        fetch(s, &mut set.vel)?;
        fetch(s, &mut set.stress)?;
        fetch(s, &mut set.rho)?;
        fetch(s, &mut set.p)?;
        fetch(s, &mut set.kind)?;
        fetch(s, &mut set.id)?;
        fetch(s, &mut set.group)?;
        s.synchronize()?;
        let n = set.n;
        fn host<T: ValidAsZeroBits + Copy>(l: &Option<Lane<T>>) -> Result<&[T], DriverError> {
            l.as_ref().map_or(Ok(&[][..]), |l| l.host.as_slice())
        }
        let first = |v: &[f32]| v[..n.min(v.len())].to_vec();
        let (pos, vel, stress) = (host(&set.pos)?, host(&set.vel)?, host(&set.stress)?);
        let rho = first(host(&set.rho)?);
        let p = first(host(&set.p)?);
        let kind = host(&set.kind)?
            .iter()
            .take(n)
            .copied()
            .collect::<Vec<u8>>();
        let id = host(&set.id)?.iter().take(n).copied().collect::<Vec<u32>>();
        let group = host(&set.group)?
            .iter()
            .take(n)
            .copied()
            .collect::<Vec<u32>>();
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
            position: vectors(pos, vstride::<D>()),
            velocity: vectors(vel, VEL_STRIDE),
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
        let mut set = self
            .set
            .take()
            .expect("a pending frame holds its staging set");
        let r = self.download(&mut set);
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
