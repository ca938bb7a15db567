//! The nearest of a fixed set of points to a query point: a k-d tree whose nodes keep the
//! bounding box of their points, so that a query skips every node no nearer than the best
//! point found so far. A query costs O(log n) on scattered points and also where many
//! points coincide or the query lies far outside the set (cases where a uniform grid with
//! a widening search, the earlier `compare --match position`, cost O(n) per query: issue
//! #52). Points with a non-finite coordinate are left out; a non-finite query finds none.

type P3 = [f64; 3];

/// At most this many points in a leaf.
const LEAF: usize = 8;

struct Node {
    lo: P3,
    hi: P3,
    /// The node's points: `order[start..end]`.
    start: usize,
    end: usize,
    /// Children (indices in `nodes`), none for a leaf.
    kids: Option<(usize, usize)>,
}

pub struct NearestIndex {
    points: Vec<P3>,
    /// Indices into `points`, grouped by node.
    order: Vec<usize>,
    nodes: Vec<Node>,
}

fn dist2(a: &P3, b: &P3) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum()
}

/// Squared distance from `q` to the box [lo, hi] (0 inside).
fn box_dist2(q: &P3, lo: &P3, hi: &P3) -> f64 {
    (0..3)
        .map(|k| (lo[k] - q[k]).max(q[k] - hi[k]).max(0.0).powi(2))
        .sum()
}

impl NearestIndex {
    /// An index over `points` (positions in any length unit; the distances come back in it).
    pub fn new(points: Vec<P3>) -> NearestIndex {
        let order: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].iter().all(|x| x.is_finite()))
            .collect();
        let mut t = NearestIndex {
            points,
            order,
            nodes: Vec::new(),
        };
        if !t.order.is_empty() {
            t.build(0, t.order.len());
        }
        t
    }

    /// Build the node of `order[start..end]` (non-empty) and its subtree; returns its index.
    fn build(&mut self, start: usize, end: usize) -> usize {
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for &i in &self.order[start..end] {
            for k in 0..3 {
                lo[k] = lo[k].min(self.points[i][k]);
                hi[k] = hi[k].max(self.points[i][k]);
            }
        }
        let me = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            start,
            end,
            kids: None,
        });
        // Coincident points (a zero-size box) stay in one leaf however many: every query
        // takes them at once or not at all.
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        if end - start <= LEAF || hi[axis] <= lo[axis] {
            return me;
        }
        let mid = start + (end - start) / 2;
        let points = &self.points;
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            points[a][axis].total_cmp(&points[b][axis]).then(a.cmp(&b))
        });
        let left = self.build(start, mid);
        let right = self.build(mid, end);
        self.nodes[me].kids = Some((left, right));
        me
    }

    /// The index (in the `points` given to `new`) and distance of the point nearest to
    /// `q`; None where the set is empty or `q` is not finite. Of points at the same
    /// distance, the one the search meets first (deterministic for a given set).
    pub fn nearest(&self, q: &P3) -> Option<(usize, f64)> {
        if self.nodes.is_empty() || !q.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut best: Option<(usize, f64)> = None;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let bound = best.map_or(f64::INFINITY, |b| b.1);
            if box_dist2(q, &node.lo, &node.hi) >= bound {
                continue;
            }
            match node.kids {
                None => {
                    // Coincident points are all as near as the first.
                    let end = if node.lo == node.hi {
                        node.start + 1
                    } else {
                        node.end
                    };
                    for &i in &self.order[node.start..end] {
                        let d = dist2(q, &self.points[i]);
                        if best.is_none_or(|b| d < b.1) {
                            best = Some((i, d));
                        }
                    }
                }
                Some((a, b)) => {
                    // The nearer child is searched first (pushed last).
                    let da = box_dist2(q, &self.nodes[a].lo, &self.nodes[a].hi);
                    let db = box_dist2(q, &self.nodes[b].lo, &self.nodes[b].hi);
                    if da <= db {
                        stack.extend([b, a]);
                    } else {
                        stack.extend([a, b]);
                    }
                }
            }
        }
        best.map(|(i, d)| (i, d.sqrt()))
    }
}
