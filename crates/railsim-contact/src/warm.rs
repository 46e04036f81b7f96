//! Warm start of the travelling: in a time integration one wheel is evaluated at poses that
//! differ by micrometres, and most of a cold travelling certifies again that the flange and the
//! field side are far from the rail. A [`WarmStart`] keeps, for every pair of the previous
//! travellings, a lower bound of the gap at the last pose, lowers the bounds by how far the
//! wheel can have moved, and travels only windows around the places where the bounds no longer
//! exclude contact. For the Hertz models' single-point search it holds instead the broad phase's
//! query with a margin ([`crate::broad::BroadMemory`], `docs/models/contact.md` §3.2).
//!
//! **Certificate** (`docs/models/contact.md` §3.1). With `|g''| <= kb` along the rail arc (the
//! bound the cold travelling's step control rests on, [`crate::pair::WheelRailPair::kappa_bound`]),
//! a gap that is at least `A` and `B` at the ends of an interval of length `h` is at least
//! `min(A, B) - kb h^2 / 8` inside it. The gap at a rail point is the signed distance to the
//! wheel's surface in the cross-section plane, so a rigid move of the wheel that displaces the
//! surface near the pair by `Δp` in that plane changes it by at most `|Δp|` (the distance is
//! 1-Lipschitz), and near contact by at most `|n·Δp| + (2 ts + 0.02)|Δp| + kb |Δp|^2` (first-order
//! Taylor term along the pair normal `n`, whose angle to the distance direction is within that of
//! the two tangents, `ts` its sine, plus the curvature term). Each bound is lowered by
//! `1.1 d + 1 nm` per evaluation, `d` the smaller of the two (the factor covers the locus of a
//! yawed wheel, which is not a fixed material line, and the isosceles gap's second-order
//! difference to the distance).
//!
//! **Same result as a cold travelling.** The windows are travelled with the rail-anchored pairs of
//! the cold travelling (the nodes `k * step` and their dyadic midpoints) from two nodes before to
//! two nodes after every interval whose bound is not positive. A patch uses its zone and two
//! pairs on each side (`crate::model::PatchInput::pair_range` and the yawed locus curvature), and
//! the cold travelling also anchors two nodes on each side of every zone
//! ([`crate::geometry::travel`]), so both see the same pairs; they differ only by where the
//! Newton iterations of the pairs start, i.e. within the travelling's angle tolerance.
//!
//! **When it travels cold instead:** no previous travelling, a move of more than 1 mm or 2 mrad
//! since it, a window reaching past the range the last cold travelling covered, a profile's end
//! inside a window, or windows with more nodes than the last cold travelling had pairs (then
//! the cold travelling is cheaper and refreshes every bound).

use crate::broad::BroadMemory;
use crate::geometry::{
    FAR_GAP, IsoPair, PoseCtx, RunEnd, TravelOptions, TravelStats, anchored_run, interpolate_s_w,
};
use crate::pair::WheelRailPair;
use crate::pose::{mat_t_vec, mat_vec};

/// \[m\] largest move of the wheel centre between two evaluations for a warm start.
const MAX_MOVE: f64 = 1e-3;
/// \[rad\] largest change of the rotation (Frobenius norm of the difference) for a warm start.
const MAX_TURN: f64 = 2e-3;

/// What is known about the gap at one pair of an earlier travelling.
#[derive(Clone, Copy, Debug, Default)]
struct Bound {
    /// \[m\] rail arc length
    s_r: f64,
    /// \[m\] wheel arc length (a guess for the pair at this rail point)
    s_w: f64,
    /// \[m\] lower bound of the gap at the last evaluated pose
    lb: f64,
    /// \[m\] the pair's wheel point in wheelset axes, relative to the wheel centre
    body: [f64; 3],
    /// \[1/m\] bounds on the wheel profile's and the rail's curvature over the window ahead (the
    /// wheel's is scaled by the locus factor of the pose it is used at)
    kappa: [f64; 2],
    /// the pair's normal in wheelset axes (rotates with the wheel)
    n_body: [f64; 3],
    /// |sine of the angle between the two tangents|, where the pair was near contact (gap up to
    /// `FAR_GAP` when travelled); `None` elsewhere
    near_ts: Option<f64>,
}

impl Bound {
    /// \[1/m\] bound on the relative curvature over the window ahead at the pose `ctx` (as
    /// [`crate::geometry::kb_at`]).
    #[inline]
    fn kb(&self, ctx: &PoseCtx) -> f64 {
        (ctx.kappa_scale * self.kappa[0] + self.kappa[1]).max(1.0)
    }
}

/// Warm-start memory of one wheel (one per wheel: it describes that wheel's last pose).
/// Grows to the size of one travelling and then allocates nothing.
#[derive(Clone, Debug, Default)]
pub struct WarmStart {
    bounds: Vec<Bound>,
    scratch: Vec<Bound>,
    /// node ranges of the windows, and the index range of their pairs in the output
    windows: Vec<(i64, i64, usize, usize)>,
    /// rotation and wheel centre of the last evaluated pose
    r: [[f64; 3]; 3],
    c: [f64; 3],
    valid: bool,
    /// pairs of the last cold travelling
    cold_pairs: usize,
    /// Warm searches since the start (travellings, or point searches that reused the stored
    /// broad-phase query).
    pub warm_count: u64,
    /// Cold searches since the start.
    pub cold_count: u64,
    /// The single-point search's broad phase (`crate::point`, models `linear`, `polach`,
    /// `fastsim`): a query that serves while the wheel stays within its margin. Its searches
    /// count in `warm_count` (a stored query reused) and `cold_count` (a new query).
    pub(crate) broad: BroadMemory,
}

impl WarmStart {
    /// Empty memory: the next travelling is cold.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forget the last travelling and broad-phase query (the next search is cold).
    pub fn invalidate(&mut self) {
        self.valid = false;
        self.broad.invalidate();
    }

    /// Forget the last travelling only.
    pub(crate) fn invalidate_travel(&mut self) {
        self.valid = false;
    }

    /// Remember a cold travelling's pairs `pairs` at the pose `ctx`.
    pub(crate) fn store_cold(&mut self, pair: &WheelRailPair, ctx: &PoseCtx, pairs: &[IsoPair]) {
        self.bounds.clear();
        // Windows add at most the nodes of a cold travelling and three midpoints per node: with
        // this capacity the splices never allocate.
        let cap = 5 * pairs.len() + 16;
        self.bounds.reserve(cap);
        self.scratch.reserve(cap);
        self.windows.reserve(16);
        self.bounds
            .extend(pairs.iter().map(|p| bound_of(pair, ctx, p)));
        self.r = ctx.r;
        self.c = ctx.c;
        self.cold_pairs = pairs.len();
        self.cold_count += 1;
        self.valid = self.bounds.len() >= 3 && self.bounds[0].lb > 0.0;
    }

    /// Travel warm to the pose `ctx`: the pairs of the windows go to `out` (cleared first).
    /// Returns `false` when a cold travelling is needed instead (`out` is then to be refilled).
    pub(crate) fn travel(
        &mut self,
        pair: &WheelRailPair,
        ctx: &PoseCtx,
        opts: &TravelOptions,
        out: &mut Vec<IsoPair>,
        stats: &mut TravelStats,
    ) -> bool {
        out.clear();
        if !self.valid {
            return false;
        }
        // The move since the last pose: wheel centre and rotation.
        let dc = [
            ctx.c[0] - self.c[0],
            ctx.c[1] - self.c[1],
            ctx.c[2] - self.c[2],
        ];
        let mut dr = [[0.0; 3]; 3];
        let mut turn2 = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                dr[i][j] = ctx.r[i][j] - self.r[i][j];
                turn2 += dr[i][j] * dr[i][j];
            }
        }
        if (dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2]).sqrt() > MAX_MOVE
            || turn2.sqrt() > MAX_TURN
        {
            self.valid = false;
            return false;
        }
        // Lower every bound by what the move can change the gap: at most the cross-section
        // displacement of its wheel point; near contact its component along the normal, plus the
        // tangential part times the angle between normal and distance direction, plus the
        // curvature term.
        for b in &mut self.bounds {
            let dp = mat_vec(&dr, b.body);
            let (d_y, d_z) = (dp[1] + dc[1], dp[2] + dc[2]);
            let len = (d_y * d_y + d_z * d_z).sqrt();
            let d = match b.near_ts {
                Some(ts) => {
                    let n = mat_vec(&ctx.r, b.n_body);
                    let normal = (n[1] * d_y + n[2] * d_z).abs();
                    len.min(normal + len * (2.0 * ts + 0.02) + b.kb(ctx) * len * len)
                }
                None => len,
            };
            b.lb -= 1.1 * d + 1e-9;
        }
        self.r = ctx.r;
        self.c = ctx.c;
        let n = self.bounds.len();
        if self.bounds[0].lb <= 0.0 || self.bounds[n - 1].lb <= 0.0 {
            self.valid = false;
            return false;
        }
        // Windows: node ranges around every interval whose bound does not exclude contact.
        let hs = opts.step;
        self.windows.clear();
        let mut nodes = 0i64;
        for i in 0..n - 1 {
            let (a, b) = (&self.bounds[i], &self.bounds[i + 1]);
            let h = b.s_r - a.s_r;
            if a.lb.min(b.lb) - 0.125 * a.kb(ctx).max(b.kb(ctx)) * h * h > 0.0 {
                continue;
            }
            let k0 = (a.s_r / hs + 1e-9).floor() as i64 - 2;
            let k1 = (b.s_r / hs - 1e-9).ceil() as i64 + 2;
            match self.windows.last_mut() {
                Some(w) if k0 <= w.1 + 1 => {
                    nodes += (k1 - w.1).max(0);
                    w.1 = w.1.max(k1);
                }
                _ => {
                    nodes += k1 - k0 + 1;
                    self.windows.push((k0, k1, 0, 0));
                }
            }
        }
        let (s_first, s_last) = (self.bounds[0].s_r, self.bounds[n - 1].s_r);
        if nodes as usize > self.cold_pairs
            || self
                .windows
                .first()
                .is_some_and(|w| (w.0 as f64) * hs < s_first)
            || self
                .windows
                .last()
                .is_some_and(|w| (w.1 as f64) * hs > s_last)
        {
            self.valid = false;
            return false;
        }
        // Travel the windows.
        for wi in 0..self.windows.len() {
            let (k0, k1, _, _) = self.windows[wi];
            let s0 = k0 as f64 * hs;
            // (s0 lies within the bounds: checked above)
            let guess =
                interpolate_s_w(&self.bounds, s0, |b| (b.s_r, b.s_w)).unwrap_or(self.bounds[0].s_w);
            let i0 = out.len();
            if anchored_run(pair, ctx, opts, k0, guess, RunEnd::At(k1), out, stats).is_none() {
                out.clear();
                self.valid = false;
                return false;
            }
            self.windows[wi].2 = i0;
            self.windows[wi].3 = out.len();
        }
        // Splice: the windows' fresh pairs replace the bounds they cover.
        self.scratch.clear();
        let mut j = 0;
        for &(k0, k1, i0, i1) in &self.windows {
            let (s0, s1) = (k0 as f64 * hs - 1e-12, k1 as f64 * hs + 1e-12);
            while j < n && self.bounds[j].s_r < s0 {
                self.scratch.push(self.bounds[j]);
                j += 1;
            }
            while j < n && self.bounds[j].s_r <= s1 {
                j += 1;
            }
            self.scratch
                .extend(out[i0..i1].iter().map(|p| bound_of(pair, ctx, p)));
        }
        self.scratch.extend_from_slice(&self.bounds[j..]);
        std::mem::swap(&mut self.bounds, &mut self.scratch);
        self.warm_count += 1;
        true
    }
}

/// The bound of a freshly travelled pair: its gap less 0.2 % (far pairs are corrected only to
/// 0.05 rad, which measures the gap to 0.1 %) and 1 nm.
fn bound_of(pair: &WheelRailPair, ctx: &PoseCtx, p: &IsoPair) -> Bound {
    // wheelset axes: R^T (point - centre), R^T n
    let body = mat_t_vec(
        &ctx.r,
        [p.x - ctx.c[0], p.a[0] - ctx.c[1], p.a[1] - ctx.c[2]],
    );
    let n_body = mat_t_vec(&ctx.r, [0.0, p.n[0], p.n[1]]);
    Bound {
        s_r: p.s_r,
        s_w: p.s_w,
        lb: p.gap - 2e-3 * p.gap.abs() - 1e-9,
        body,
        kappa: pair.kappa_ahead(p.s_w, p.s_r),
        n_body,
        near_ts: (p.gap <= FAR_GAP).then_some(p.tangent_sin.abs()),
    }
}
