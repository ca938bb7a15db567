//! Spatial indices of the scene generator (`generate.rs`), so that its cost grows with
//! the particles and objects, not with their product (issue #52: one block per particle
//! took 26.9 s to check at 80,452 blocks):
//! * `Grid`: a hash grid of points, asked whether any lies within r of a point;
//! * `Tiles`: the particles kept so far, in coarse tiles, asked for those inside a box;
//! * `BoxIndex`: objects' bounding boxes in coarse bins, asked which may hold a point.
//!
//! Positions and sizes are in the scene's length unit [L].

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use rayon::prelude::*;

pub(super) type P3 = [f64; 3];

/// Below this many points, work on one thread: rayon's start costs more.
pub(super) const PARALLEL_FROM: usize = 4096;

/// A hash grid of positions with cell size `cell`, built once and then read from every
/// thread: per cell a chain of indices through `next` (no allocation per cell), and a bit
/// per cell of the points' bounding box saying which cells hold any, so that most empty
/// cells cost no hash lookup.
pub(super) struct Grid {
    cell: f64,
    /// Per packed cell key (`pack`): the last point of that cell, `NONE` ends a chain.
    heads: HashMap<u64, u32, BuildHasherDefault<CellHasher>>,
    points: Vec<P3>,
    /// Per point: the point before it in the same cell (or in one that shares its packed
    /// key), `NONE` where none.
    next: Vec<u32>,
    /// The occupied cells, where the bounding box has at most `Occupied::MAX_CELLS` cells.
    occupied: Option<Occupied>,
}

const NONE: u32 = u32::MAX;

/// Packs a cell's integer coordinates into one key, 21 bits each: cells 2^21 apart on an
/// axis share a key, which only adds candidates that the distance test then rejects.
fn pack(k: [i64; 3]) -> u64 {
    const M: u64 = (1 << 21) - 1;
    (k[0] as u64 & M) | ((k[1] as u64 & M) << 21) | ((k[2] as u64 & M) << 42)
}

/// The hash of a packed cell key (the finaliser of MurmurHash3): `HashMap`'s default
/// SipHash took half of a large scene's set-up.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ u64::from(*b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = x;
    }
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// One bit per cell of the box of cells `lo..lo + size`, x fastest.
struct Occupied {
    lo: [i64; 3],
    size: [i64; 3],
    bits: Vec<u64>,
}

impl Occupied {
    /// At most 2^30 cells (128 MiB); a larger box goes without.
    const MAX_CELLS: i64 = 1 << 30;

    fn index(&self, k: [i64; 3]) -> Option<usize> {
        let mut i = 0;
        for a in (0..3).rev() {
            let o = k[a] - self.lo[a];
            if o < 0 || o >= self.size[a] {
                return None;
            }
            i = i * self.size[a] + o;
        }
        Some(i as usize)
    }

    fn has(&self, k: [i64; 3]) -> bool {
        self.index(k)
            .is_some_and(|i| self.bits[i / 64] >> (i % 64) & 1 == 1)
    }
}

impl Grid {
    fn key(cell: f64, p: &P3) -> [i64; 3] {
        [0, 1, 2].map(|a| (p[a] / cell).floor() as i64)
    }

    pub(super) fn new(cell: f64, points: Vec<P3>) -> Grid {
        let keys: Vec<[i64; 3]> = if points.len() < PARALLEL_FROM {
            points.iter().map(|p| Grid::key(cell, p)).collect()
        } else {
            points.par_iter().map(|p| Grid::key(cell, p)).collect()
        };
        let mut heads: HashMap<u64, u32, _> = HashMap::default();
        heads.reserve(points.len());
        let mut next = Vec::with_capacity(points.len());
        for (i, k) in keys.iter().enumerate() {
            next.push(heads.insert(pack(*k), i as u32).unwrap_or(NONE));
        }
        let occupied = keys.first().and_then(|first| {
            let (mut lo, mut hi) = (*first, *first);
            for k in &keys {
                for a in 0..3 {
                    lo[a] = lo[a].min(k[a]);
                    hi[a] = hi[a].max(k[a]);
                }
            }
            let size = [0, 1, 2].map(|a| hi[a] - lo[a] + 1);
            let cells = size
                .iter()
                .try_fold(1i64, |n, &s| n.checked_mul(s))
                .filter(|&n| n <= Occupied::MAX_CELLS)?;
            let mut o = Occupied {
                lo,
                size,
                bits: vec![0; (cells as usize).div_ceil(64)],
            };
            for k in &keys {
                let i = o.index(*k).expect("inside the bounding box");
                o.bits[i / 64] |= 1 << (i % 64);
            }
            Some(o)
        });
        Grid {
            cell,
            heads,
            points,
            next,
            occupied,
        }
    }

    /// Whether a point of the grid lies closer than `r` (at most the cell size) to `p`.
    /// Only the cells that the ball of radius `r` reaches are searched (of the 27 around
    /// `p`'s own): 8 where `r` is half a cell.
    pub(super) fn near(&self, p: &P3, r: f64) -> bool {
        self.visit_near(p, r, |_| true)
    }

    /// Calls `f(i)` for the grid's points i closer than `r` (at most the cell size) to `p`
    /// until it returns true; whether one did.
    fn visit_near(&self, p: &P3, r: f64, mut f: impl FnMut(usize) -> bool) -> bool {
        if self.points.is_empty() {
            return false;
        }
        let k = Grid::key(self.cell, p);
        let span = |a: usize| {
            let lo = ((p[a] - r) / self.cell).floor() as i64;
            let hi = ((p[a] + r) / self.cell).floor() as i64;
            lo.max(k[a] - 1)..=hi.min(k[a] + 1)
        };
        for z in span(2) {
            for y in span(1) {
                for x in span(0) {
                    if self.occupied.as_ref().is_some_and(|o| !o.has([x, y, z])) {
                        continue;
                    }
                    let mut i = self.heads.get(&pack([x, y, z])).copied().unwrap_or(NONE);
                    while i != NONE {
                        let q = &self.points[i as usize];
                        if (0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>() < r * r
                            && f(i as usize)
                        {
                            return true;
                        }
                        i = self.next[i as usize];
                    }
                }
            }
        }
        false
    }
}

impl Grid {
    /// Calls `f(i)` for every point i of the grid closer than `r` (at most the cell size)
    /// to `p`.
    pub(super) fn for_each_near(&self, p: &P3, r: f64, mut f: impl FnMut(usize)) {
        self.visit_near(p, r, |i| {
            f(i);
            false
        });
    }

    /// Point `i` as given to `new`.
    pub(super) fn point(&self, i: usize) -> &P3 {
        &self.points[i]
    }

    /// The smallest `tags[i]` of the grid's points i closer than `r` (at most the cell size)
    /// to `p`, None where none is (`tags` is indexed as the points given to `new`).
    pub(super) fn min_tag_near(&self, p: &P3, r: f64, tags: &[u32]) -> Option<u32> {
        let mut best: Option<u32> = None;
        self.visit_near(p, r, |i| {
            if best.is_none_or(|b| tags[i] < b) {
                best = Some(tags[i]);
            }
            false
        });
        best
    }
}

type CellMap<V> = HashMap<u64, V, BuildHasherDefault<CellHasher>>;

/// Points in cubic tiles `tile` wide (a few particle spacings), appended object by object
/// and asked for those inside a box: the candidates that a new object's particles may lie
/// near, found without reading every particle kept so far.
pub(super) struct Tiles {
    tile: f64,
    map: CellMap<Vec<P3>>,
}

impl Tiles {
    pub(super) fn new(tile: f64) -> Tiles {
        Tiles {
            tile,
            map: CellMap::default(),
        }
    }

    fn key(&self, p: &P3) -> [i64; 3] {
        [0, 1, 2].map(|a| (p[a] / self.tile).floor() as i64)
    }

    /// Add `points`; runs of consecutive points in one tile (a lattice runs along x) cost
    /// one lookup.
    pub(super) fn extend(&mut self, points: &[P3]) {
        let mut rest = points;
        while let Some(first) = rest.first() {
            let k = self.key(first);
            let run = rest
                .iter()
                .position(|p| self.key(p) != k)
                .unwrap_or(rest.len());
            self.map
                .entry(pack(k))
                .or_default()
                .extend_from_slice(&rest[..run]);
            rest = &rest[run..];
        }
    }

    /// The points inside [lo, hi] (closed), in no particular order.
    pub(super) fn within(&self, lo: &P3, hi: &P3) -> Vec<P3> {
        let inside = |q: &&P3| (0..3).all(|a| q[a] >= lo[a] && q[a] <= hi[a]);
        let (klo, khi) = (self.key(lo), self.key(hi));
        // Tiles of the box, or every occupied tile where those are fewer.
        let span = (0..3).try_fold(1u64, |n, a| {
            n.checked_mul(u64::try_from(khi[a] - klo[a] + 1).ok()?)
        });
        let mut out = Vec::new();
        match span {
            Some(n) if n <= self.map.len() as u64 => {
                // (Tiles 2^21 apart share a packed key, `pack`: their points may come twice,
                // which only repeats a candidate.)
                for z in klo[2]..=khi[2] {
                    for y in klo[1]..=khi[1] {
                        for x in klo[0]..=khi[0] {
                            if let Some(v) = self.map.get(&pack([x, y, z])) {
                                out.extend(v.iter().filter(inside));
                            }
                        }
                    }
                }
            }
            _ => {
                for v in self.map.values() {
                    out.extend(v.iter().filter(inside));
                }
            }
        }
        out
    }
}

/// Items' bounding boxes (closed, over the first `dim` axes) in cubic bins `bin` wide, asked
/// which items' boxes may hold a point. An item whose box spans more than `MAX_BINS` bins,
/// or is unbounded, is listed as `wide` and returned for every point: a scene has few such
/// (containers, long walls), and many small ones (blocks) cost one lookup per point.
pub(super) struct BoxIndex {
    bin: f64,
    dim: usize,
    bins: CellMap<Vec<u32>>,
    wide: Vec<u32>,
}

impl BoxIndex {
    const MAX_BINS: i64 = 64;

    /// `boxes[i]`: item i's (lo, hi), or None where it has no bounded box.
    pub(super) fn new(bin: f64, dim: usize, boxes: &[Option<(P3, P3)>]) -> BoxIndex {
        let mut ix = BoxIndex {
            bin,
            dim,
            bins: CellMap::default(),
            wide: Vec::new(),
        };
        for (i, b) in boxes.iter().enumerate() {
            let i = i as u32;
            let Some((lo, hi)) = b else {
                ix.wide.push(i);
                continue;
            };
            let (klo, khi) = (ix.key(lo), ix.key(hi));
            let n = (0..3).try_fold(1i64, |n, a| n.checked_mul(khi[a].checked_sub(klo[a])? + 1));
            if !n.is_some_and(|n| (1..=Self::MAX_BINS).contains(&n)) {
                ix.wide.push(i);
                continue;
            }
            for z in klo[2]..=khi[2] {
                for y in klo[1]..=khi[1] {
                    for x in klo[0]..=khi[0] {
                        let v = ix.bins.entry(pack([x, y, z])).or_default();
                        if v.last() != Some(&i) {
                            v.push(i);
                        }
                    }
                }
            }
        }
        ix
    }

    /// Bin coordinates; 0 on the axes past `dim` (a 2D scene's z means nothing).
    fn key(&self, p: &P3) -> [i64; 3] {
        let dim = self.dim;
        [0, 1, 2].map(|a| {
            if a < dim {
                (p[a] / self.bin).floor() as i64
            } else {
                0
            }
        })
    }

    /// Calls `f` with every item whose box may hold `p` (some more than once where
    /// packed keys meet), until it returns true; whether one did.
    pub(super) fn any(&self, p: &P3, mut f: impl FnMut(u32) -> bool) -> bool {
        if self.wide.iter().any(|&i| f(i)) {
            return true;
        }
        if self.bins.is_empty() {
            return false;
        }
        let k = pack(self.key(p));
        self.bins.get(&k).is_some_and(|v| v.iter().any(|&i| f(i)))
    }
}
