//! GPU time of the drawing's passes: `GL_TIME_ELAPSED` queries (OpenGL 3.3) around each
//! named pass, read back only once their result is available (a frame or more later), so
//! that measuring never stalls the pipeline. The means per pass come out of
//! [`GpuTimers::take`].

use glow::HasContext;

/// The mean GPU time of one named pass over the frames measured.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    /// The pass ("sprites", "blur 1 x", ..., "shade").
    pub name: &'static str,
    /// Mean GPU milliseconds per frame.
    pub ms: f64,
    /// Frames measured.
    pub frames: u32,
}

#[derive(Default)]
pub(crate) struct GpuTimers {
    /// Queries issued and not yet read, with their pass.
    pending: Vec<(&'static str, glow::Query)>,
    /// Queries read and free for reuse.
    free: Vec<glow::Query>,
    /// Whether a query is open (between [`GpuTimers::pass`] and [`GpuTimers::end`]).
    open: bool,
    /// Per pass: total nanoseconds and count, in the order first seen.
    sums: Vec<(&'static str, u64, u32)>,
    /// Set once a query cannot be made: no timing from then on.
    off: bool,
}

impl GpuTimers {
    /// Ends the open pass (if any) and starts timing `name`.
    pub(crate) unsafe fn pass(&mut self, gl: &glow::Context, name: &'static str) {
        // SAFETY: the context rule (this fn's contract).
        unsafe { self.end(gl) };
        if self.off {
            return;
        }
        let q = match self.free.pop() {
            Some(q) => q,
            // SAFETY: the context rule (this fn's contract); making a query names no object.
            None => match unsafe { gl.create_query() } {
                Ok(q) => q,
                Err(_) => {
                    self.off = true;
                    return;
                }
            },
        };
        // SAFETY: the context rule (this fn's contract); q is one of this struct's queries
        // (read and free for reuse, or made above), and no other query is open (ended
        // above).
        unsafe { gl.begin_query(glow::TIME_ELAPSED, q) };
        self.pending.push((name, q));
        self.open = true;
    }

    /// Ends the open pass, if any.
    pub(crate) unsafe fn end(&mut self, gl: &glow::Context) {
        if self.open {
            // SAFETY: the context rule (this fn's contract); a query is open (`open`).
            unsafe { gl.end_query(glow::TIME_ELAPSED) };
            self.open = false;
        }
    }

    /// Reads the queries whose results are available (in issue order: a later one is
    /// never ready before an earlier one), without waiting.
    pub(crate) unsafe fn collect(&mut self, gl: &glow::Context) {
        // SAFETY: the context rule (this fn's contract); the queries are this struct's,
        // issued and ended (the open one is left out).
        unsafe {
            let ready = self
                .pending
                .iter()
                .take(self.pending.len() - self.open as usize)
                .take_while(|(_, q)| {
                    gl.get_query_parameter_u32(*q, glow::QUERY_RESULT_AVAILABLE) != 0
                })
                .count();
            for (name, q) in self.pending.drain(..ready) {
                // Nanoseconds; a pass is far below the 4.3 s a u32 holds.
                let ns = gl.get_query_parameter_u32(q, glow::QUERY_RESULT) as u64;
                match self.sums.iter_mut().find(|s| s.0 == name) {
                    Some(s) => {
                        s.1 += ns;
                        s.2 += 1;
                    }
                    None => self.sums.push((name, ns, 1)),
                }
                self.free.push(q);
            }
        }
    }

    /// The mean time per pass since the last call (of the queries read so far), and a
    /// fresh start.
    pub(crate) unsafe fn take(&mut self, gl: &glow::Context) -> Vec<PassTime> {
        // SAFETY: the context rule (this fn's contract).
        unsafe { self.collect(gl) };
        self.sums
            .drain(..)
            .map(|(name, ns, n)| PassTime {
                name,
                ms: ns as f64 * 1e-6 / n.max(1) as f64,
                frames: n,
            })
            .collect()
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (renderer.rs): the queries are this struct's, deleted
        // only here, once.
        unsafe {
            for q in self.free.iter().chain(self.pending.iter().map(|p| &p.1)) {
                gl.delete_query(*q);
            }
        }
    }
}
