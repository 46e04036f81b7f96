//! Broad phase of the single-point contact search of the Hertz models: bounding hierarchies of
//! the two profile curves, built once per pair, and a simultaneous descent of both that returns
//! the pairs of small arcs (leaves) where the rail can touch or interpenetrate the wheel for one
//! pose. Everything else is proved out of contact by bounds, without evaluating a curve point.
//!
//! A node of an [`ArcTree`] is an arc of the curve with its chord and `thick`, the largest
//! distance of the arc from the chord (the arc lies in the capsule of that radius around the
//! chord). The wheel's nodes are mapped to the side frame by the pose: the rigid image of the
//! profile is an affine image of the chord (the linear part is a block of the rotation matrix,
//! of norm at most 1, so the thickness does not grow); the yawed contact locus
//! (`geometry` module docs) differs from the rigid image by `R (rho sin th, 0, rho (1 - cos th))`
//! with `sin th = -tan(yaw) rho'`: the chord's end points are moved by their own offsets and the
//! capsule is widened by the range of the offset over the node's rho and rho'.
//!
//! A rail arc `a` and a wheel arc `b` are dropped when, measured from the wheel chord with `u`
//! its direction and `n` its normal toward the wheel's material:
//! - the rail chord lies more than `thick_a + thick_b` on the outer side of `b`'s chord line
//!   (every rail point is then below every point of the wheel arc: no interpenetration, no touch);
//!   the same seen from the rail: the wheel chord more than the radii above `a`'s chord line;
//! - or deeper than `depth + thick_a + thick_b` on the material side (`depth` = 0.5 mm, see
//!   `crate::point` for what happens to deeper zones);
//! - or boxes around the two capsules are further apart than `depth` (the points of an
//!   interpenetrating pair are at most that far apart);
//! - or, along `u`, the two chords' extents are further apart than the lateral shift a pair of
//!   points can have across a penetration of that depth (`depth · tan(15° + θ/2 + 5°)`).
//!
//! Here θ bounds the angle between the tangents of a pair interpenetrating by at most `depth`:
//! from a crossing of the two curves to the deepest point the gap falls by at least
//! θ²/(2 κ_rel), so θ = min(60°, √(2·depth·κ_rel)) with κ_rel the largest curvature of the wheel
//! plus that of the rail (24° for the benchmark's S1002 on UIC60, κ_rel = 173 1/m); a pair's
//! normal is within θ/2 of either tangent (5° are added for the yawed locus). The side rules need the arc whose chord is used to
//! turn by less than 90° − θ/2 − 5° (its normal then stays on the same side); the extent rule by
//! less than 15°; the others hold for any arc. Source of the method: bounding-volume
//! hierarchies as in collision detection (e.g. Ericson, *Real-Time Collision Detection*, 2005,
//! ch. 6); the bounds above are derived here for the isosceles pairs of seed §3.2.

use railsim_profile::ArcCurve;

use crate::geometry::{PoseCtx, locus_cos, locus_sin, profile_slope};
use crate::pair::WheelRailPair;

/// \[m\] leaves are split until their arc deviates from the chord by at most this...
pub(crate) const LEAF_THICK: f64 = 8e-6;
/// \[m\] ... and are at most this long.
const LEAF_LEN: f64 = 16e-3;
/// cos 15°: nodes turning less than this are tested by extent too.
const COS_STRAIGHT: f64 = 0.9659;
/// \[rad\] 15°, the turning of such nodes
const STRAIGHT: f64 = 0.2618;
/// \[rad\] 5°: margin on the angle between a pair's normal and a chord's (the yawed locus'
/// tangent against the profile's, round-off)
const ANGLE_MARGIN: f64 = 0.0873;

/// One arc of an [`ArcTree`].
#[derive(Clone, Copy, Debug, Default)]
pub struct TreeNode {
    /// \[m\] arc-length range
    pub s: [f64; 2],
    /// chord end points (the curve's own frame)
    pub p0: [f64; 2],
    /// chord end points (the curve's own frame)
    pub p1: [f64; 2],
    /// \[m\] largest distance of the arc from the chord segment
    pub thick: f64,
    /// \[m\] signed offset of the arc's middle node from the chord, along the chord's left
    /// normal (for the depth estimates of the candidates)
    pub sag: f64,
    /// smallest cosine between a tangent of the arc and the chord direction
    pub cos_min: f64,
    /// unit left normal of the chord (toward the wheel on a rail)
    pub normal: [f64; 2],
    /// wheel trees: largest |rho'| on the arc, `rho' = -t_z / t_y` the profile's slope (|t_y|
    /// floored at 1e-6)
    pub slope_abs: f64,
    /// wheel trees: `rho'` at the chord's two end points
    pub slope_end: [f64; 2],
    /// wheel trees: \[m\] range of `rho rho'` on the arc (`rho = r0 - z`)
    pub m1: [f64; 2],
    /// wheel trees: \[m\] range of `rho rho'^2`
    pub m2: [f64; 2],
    /// wheel trees: \[m\] largest `rho rho'^4`
    pub m4: f64,
    /// wheel trees: \[m\] largest `rho`
    pub rho_max: f64,
    /// index of the first child (the second follows it); 0 for a leaf
    pub child: u32,
    /// the chord's bounding box: smallest and largest y, smallest and largest z (the curve's
    /// own frame; the box test uses the rail's, the wheel's chords are boxed once mapped)
    pub bbox: [f64; 4],
}

/// A bounding hierarchy of an [`ArcCurve`] over an arc-length range: binary, split at the
/// middle node until the arcs are flatter than 8 µm and shorter than 16 mm (`LEAF_THICK`,
/// `LEAF_LEN`). Node 0 is the root. A wheel's tree also keeps the ranges that bound its yawed
/// contact locus.
#[derive(Clone, Debug, Default)]
pub struct ArcTree {
    /// The nodes; node 0 is the root.
    pub nodes: Vec<TreeNode>,
}

impl ArcTree {
    /// Build the hierarchy of `curve` over arc lengths `[s0, s1]`; `r0` \[m\] is the nominal
    /// radius of a wheel profile (rho = r0 - z; any value for a rail).
    pub fn new(curve: &ArcCurve, s0: f64, s1: f64, r0: f64) -> ArcTree {
        let ds = curve.ds();
        let pts = curve.nodes();
        let last = pts.len() - 1;
        let i0 = ((s0 / ds).floor() as usize).min(last - 1);
        let i1 = ((s1 / ds).ceil() as usize).clamp(i0 + 1, last);
        let mut tree = ArcTree { nodes: vec![] };
        tree.nodes.push(TreeNode::default());
        tree.fill(0, curve, r0, i0, i1);
        tree
    }

    fn fill(&mut self, slot: usize, curve: &ArcCurve, r0: f64, i0: usize, i1: usize) {
        let ds = curve.ds();
        let pts = &curve.nodes()[i0..=i1];
        let (a, b) = (pts[0].p, pts[pts.len() - 1].p);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt().max(1e-15);
        let u = [d[0] / len, d[1] / len];
        let (mut thick, mut cos_min, mut kmax) = (0.0f64, 1.0f64, 0.0f64);
        let empty = [f64::INFINITY, f64::NEG_INFINITY];
        let (mut m1, mut m2, mut m4, mut slope_abs, mut rho_max) =
            (empty, empty, 0.0f64, 0.0f64, 0.0f64);
        // largest change of rho rho' and rho rho'^2 between neighbouring nodes: the slack of the
        // ranges between nodes
        let (mut d1, mut d2, mut prev) = (0.0f64, 0.0f64, None::<(f64, f64)>);
        for c in pts {
            let v = [c.p[0] - a[0], c.p[1] - a[1]];
            let along = v[0] * u[0] + v[1] * u[1];
            let dist = if along < 0.0 {
                (v[0] * v[0] + v[1] * v[1]).sqrt()
            } else if along > len {
                ((c.p[0] - b[0]).powi(2) + (c.p[1] - b[1]).powi(2)).sqrt()
            } else {
                (v[0] * u[1] - v[1] * u[0]).abs()
            };
            thick = thick.max(dist);
            cos_min = cos_min.min(c.t[0] * u[0] + c.t[1] * u[1]);
            let (q, rho) = (profile_slope(c.t), r0 - c.p[1]);
            let (a1, a2) = (rho * q, rho * q * q);
            m1 = [m1[0].min(a1), m1[1].max(a1)];
            m2 = [m2[0].min(a2), m2[1].max(a2)];
            m4 = m4.max(a2 * q * q);
            slope_abs = slope_abs.max(q.abs());
            rho_max = rho_max.max(rho);
            if let Some((b1, b2)) = prev {
                d1 = d1.max((a1 - b1).abs());
                d2 = d2.max((a2 - b2).abs());
            }
            prev = Some((a1, a2));
            kmax = kmax.max(c.kappa.abs());
        }
        // Between the resampled nodes the curve is a cubic Hermite arc; it leaves the polygon
        // of the nodes by at most about kappa ds^2 / 8 (doubled, and a nanometre of round-off).
        thick += 0.25 * kmax * ds * ds + 1e-9;
        let pm = pts[pts.len() / 2].p;
        let sag = (pm[1] - a[1]) * u[0] - (pm[0] - a[0]) * u[1];
        let s_range = [i0 as f64 * ds, (i1 as f64 * ds).min(curve.length())];
        self.nodes[slot] = TreeNode {
            s: s_range,
            p0: a,
            p1: b,
            thick,
            sag,
            cos_min,
            normal: [-u[1], u[0]],
            slope_abs,
            slope_end: [profile_slope(pts[0].t), profile_slope(pts[pts.len() - 1].t)],
            m1: [m1[0] - d1, m1[1] + d1],
            m2: [m2[0] - d2, m2[1] + d2],
            m4: m4 * 1.01,
            rho_max: rho_max + 0.5 * kmax * ds * ds,
            child: 0,
            bbox: chord_box(a, b),
        };
        let leaf = (thick <= LEAF_THICK && s_range[1] - s_range[0] <= LEAF_LEN) || i1 - i0 <= 4;
        if !leaf {
            let c = self.nodes.len();
            self.nodes.push(TreeNode::default());
            self.nodes.push(TreeNode::default());
            self.nodes[slot].child = c as u32;
            let mid = (i0 + i1) / 2;
            self.fill(c, curve, r0, i0, mid);
            self.fill(c + 1, curve, r0, mid, i1);
        }
    }
}

/// A rail leaf and a wheel leaf that the bounds could not separate, with estimates from the
/// chords: the rail point of largest depth into the wheel and its wheel partner.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Candidate {
    /// rail leaf's arc-length range
    pub s_r: [f64; 2],
    /// \[m\] estimated depth of the rail arc into the wheel arc (the deepest of the rail chord's
    /// ends and the rail arc's middle, both arcs taken as parabolas; negative: a gap)
    pub depth: f64,
    /// estimated rail arc length of the deepest point
    pub s_r_est: f64,
    /// estimated wheel arc length of its partner
    pub s_w_est: f64,
    /// wheel leaf's arc-length range
    pub s_w: [f64; 2],
    /// indices of the rail and the wheel leaf in their trees (`u32::MAX`: not a pair of leaves)
    pub leaves: [u32; 2],
}

/// Reusable buffers of the broad phase: the candidates and the wheel nodes' chords mapped for
/// the current pose (each computed once per pose, on first use).
#[derive(Clone, Debug, Default)]
pub struct BroadScratch {
    /// The candidates of the last query.
    pub candidates: Vec<Candidate>,
    /// per wheel node: query stamp and chord in the side frame
    chords: Vec<(u32, WheelChord)>,
    stamp: u32,
}

/// The wheel nodes' map from profile to side frame for one pose.
struct WheelMap {
    /// side-frame (y, z) of the profile origin
    c: [f64; 2],
    /// linear part: side (y, z) = c + m (py, pz)
    m: [[f64; 2]; 2],
    /// tan yaw, 0 without yaw
    tan_yaw: f64,
    /// rotation entries mapping the locus offset (x, z components) to side (y, z)
    rx: [f64; 2],
    rz: [f64; 2],
    /// |rx0| + |rx1|, |rz0| + |rz1|
    ax: f64,
    az: f64,
    r0: f64,
}

impl WheelMap {
    fn new(pair: &WheelRailPair, ctx: &PoseCtx) -> Self {
        let r = &ctx.r;
        // locus (no yaw): y = c1 + r11 axial - r12 rho with axial = y0 + py, rho = r0 - pz.
        let m = [[r[1][1], r[1][2]], [r[2][1], r[2][2]]];
        let (ax, mr) = (pair.wheel_y0, -pair.r0);
        WheelMap {
            c: [
                ctx.c[1] + m[0][0] * ax + m[0][1] * mr,
                ctx.c[2] + m[1][0] * ax + m[1][1] * mr,
            ],
            m,
            tan_yaw: ctx.locus_tan_yaw(),
            rx: [r[1][0], r[2][0]],
            rz: [r[1][2], r[2][2]],
            ax: r[1][0].abs() + r[2][0].abs(),
            az: r[1][2].abs() + r[2][2].abs(),
            r0: pair.r0,
        }
    }

    /// The yawed locus' offset from the rigid image, `R (rho st, 0, rho (1 - ct))`, (y, z).
    #[inline]
    fn offset(&self, rho: f64, rho_p: f64) -> [f64; 2] {
        let st = locus_sin(self.tan_yaw, rho_p);
        let (a, b) = (rho * st, rho * (1.0 - locus_cos(st)));
        [
            self.rx[0] * a + self.rz[0] * b,
            self.rx[1] * a + self.rz[1] * b,
        ]
    }

    /// The node's chord in the side frame (end points on the locus) and its capsule radius.
    #[inline]
    fn chord(&self, n: &TreeNode) -> WheelChord {
        let q = |p: [f64; 2]| {
            [
                self.c[0] + self.m[0][0] * p[0] + self.m[0][1] * p[1],
                self.c[1] + self.m[1][0] * p[0] + self.m[1][1] * p[1],
            ]
        };
        let (mut q0, mut q1) = (q(n.p0), q(n.p1));
        if self.tan_yaw == 0.0 {
            return WheelChord::new(q0, q1, n.thick);
        }
        let (o0, o1) = (
            self.offset(self.r0 - n.p0[1], n.slope_end[0]),
            self.offset(self.r0 - n.p1[1], n.slope_end[1]),
        );
        q0 = [q0[0] + o0[0], q0[1] + o0[1]];
        q1 = [q1[0] + o1[0], q1[1] + o1[1]];
        // Inside the node the offset stays within its range over the node, and so does the
        // interpolation between the end offsets: the range bounds the widening. With
        // st = -T rho' (|T rho'| <= 0.5), rho st = -T rho rho' and, by the series of cos,
        // rho (1 - ct) = T^2 rho rho'^2 (1/2 + e) with 0 <= e <= 0.14 T^2 rho'^2.
        let t = self.tan_yaw.abs();
        let widen = if t * n.slope_abs <= 0.5 {
            t * (n.m1[1] - n.m1[0]) * self.ax
                + t * t * (0.5 * (n.m2[1] - n.m2[0]) + 0.14 * t * t * n.m4) * self.az
        } else {
            // the clamp of sin theta at 0.5 acts somewhere on the node: the whole offset
            n.rho_max * (0.5 * self.ax + 0.14 * self.az)
        };
        WheelChord::new(q0, q1, n.thick + widen)
    }
}

/// The constants of the rules for one query.
#[derive(Clone, Copy, Debug)]
struct Rules {
    /// \[m\] deepest interpenetration of interest
    depth: f64,
    /// side rules: a node's tangents within 90° - half of its chord
    cos_side: f64,
    /// extent rule (nodes turning less than 15°): lateral shift per unit depth
    tan_shift: f64,
    /// \[m\] added to every wheel capsule: how far any locus point may move before the result
    /// is used (0 for a query at the pose itself)
    margin: f64,
    /// the rules that rest on the directions of the wheel arcs' tangents (the side rule seen
    /// from the wheel and the extent rule); off with a margin, where the wheel may turn
    wheel_angles: bool,
}

impl Rules {
    /// The rules of a query at `depth` with `margin`, for a wheel locus whose curvature is at
    /// most `kappa_scale` times the profile's (`PoseCtx::kappa_scale`).
    fn new(pair: &WheelRailPair, depth: f64, margin: f64, kappa_scale: f64) -> Self {
        // A pair interpenetrating by at most `depth` has tangents at most theta apart, theta^2 =
        // 2 depth kappa_rel (the gap falls from a crossing to its minimum by at least
        // theta^2 / (2 kappa_rel)), capped at 60°; its normal is within theta / 2 of either
        // tangent.
        let kappa_rel = kappa_scale * pair.wheel_kappa_max + pair.rail_kappa_max;
        let half = 0.5
            * (2.0 * depth * kappa_rel)
                .sqrt()
                .min(std::f64::consts::FRAC_PI_3)
            + ANGLE_MARGIN;
        Rules {
            depth,
            cos_side: half.sin(),
            tan_shift: (STRAIGHT + half).tan(),
            margin,
            wheel_angles: margin == 0.0,
        }
    }
}

/// The chord geometry of a node pair that the rules could not separate, for the estimates.
struct Overlap {
    /// the wheel chord (q1 - q0) and its squared length and length
    d: [f64; 2],
    len2: f64,
    len: f64,
    /// the rail chord's end points from q0
    v0: [f64; 2],
    v1: [f64; 2],
}

/// The rules of the module docs for rail node `a` and the wheel node mapped to `w` (its chord,
/// capsule radius and chord length, [`mapped`]): `None` when they separate the two arcs.
#[inline(always)]
fn overlap(a: &TreeNode, b: &TreeNode, w: &WheelChord, r: &Rules) -> Option<Overlap> {
    let (q0, q1) = (w.q0, w.q1);
    let t = a.thick + w.thick + r.margin;
    let depth = r.depth;
    // boxes around the two capsules, further apart than the depth: no pair of points of the
    // two arcs is closer than that (|P - Q| = -gap for a penetrating pair)
    let m = t + depth;
    let (ba, bw) = (&a.bbox, &w.bbox);
    if ba[0] > bw[1] + m || ba[1] < bw[0] - m || ba[2] > bw[3] + m || ba[3] < bw[2] - m {
        return None;
    }
    // The wheel arc more than the radii above the rail chord's line (the same rule seen from
    // the rail, where the rail arc turns by less than 60°): no rail point is above it.
    let (w0, w1) = (
        (q0[0] - a.p0[0]) * a.normal[0] + (q0[1] - a.p0[1]) * a.normal[1],
        (q1[0] - a.p0[0]) * a.normal[0] + (q1[1] - a.p0[1]) * a.normal[1],
    );
    if a.cos_min >= r.cos_side && w0 > t && w1 > t {
        return None;
    }
    // Offsets toward the wheel's material (the left normal of the field-ward chord) and
    // positions along the chord, both times the chord length `len`.
    let (d, len) = ([q1[0] - q0[0], q1[1] - q0[1]], w.len);
    let len2 = len * len;
    let v0 = [a.p0[0] - q0[0], a.p0[1] - q0[1]];
    let v1 = [a.p1[0] - q0[0], a.p1[1] - q0[1]];
    let (o0, o1) = (d[0] * v0[1] - d[1] * v0[0], d[0] * v1[1] - d[1] * v1[0]);
    // (plain comparisons: the operands are finite, and `f64::max` costs its NaN handling)
    let (o_min, o_max) = if o0 <= o1 { (o0, o1) } else { (o1, o0) };
    // o_max / len + t < 0 (the side rule seen from the wheel), and o_min / len - t > depth
    // (deeper than the depth of interest)
    if (r.wheel_angles && b.cos_min >= r.cos_side && o_max < -t * len) || o_min > (t + depth) * len
    {
        return None;
    }
    if r.wheel_angles && b.cos_min >= COS_STRAIGHT {
        let (e0, e1) = (v0[0] * d[0] + v0[1] * d[1], v1[0] * d[0] + v1[1] * d[1]);
        let shift = r.tan_shift * (o_max + t * len).min((depth + t) * len) + t * len;
        if (e0 < -shift && e1 < -shift) || (e0 > len2 + shift && e1 > len2 + shift) {
            return None;
        }
    }
    Some(Overlap {
        d,
        len2,
        len,
        v0,
        v1,
    })
}

/// The candidate of leaves `a` (rail, index `ia`) and `b` (wheel, `ib`). Estimates: of the rail
/// chord's end points and the rail arc's middle, the deepest below the wheel arc, the arcs taken
/// as parabolas through their chords and middles.
#[inline]
fn estimate(a: &TreeNode, b: &TreeNode, ia: u32, ib: u32, o: &Overlap) -> Candidate {
    let (d, len2, v0, v1) = (o.d, o.len2, o.v0, o.v1);
    let inv = 1.0 / o.len;
    let n_r = a.normal;
    let vm = [
        0.5 * (v0[0] + v1[0]) + a.sag * n_r[0],
        0.5 * (v0[1] + v1[1]) + a.sag * n_r[1],
    ];
    let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
    for (v, s_r) in [(v0, a.s[0]), (v1, a.s[1]), (vm, 0.5 * (a.s[0] + a.s[1]))] {
        let tau = ((v[0] * d[0] + v[1] * d[1]) / len2).clamp(0.0, 1.0);
        let est = (d[0] * v[1] - d[1] * v[0]) * inv - 4.0 * tau * (1.0 - tau) * b.sag;
        if est > best.0 {
            best = (est, s_r, tau);
        }
    }
    let (est, s_r_est, f) = best;
    Candidate {
        s_r: a.s,
        depth: est,
        s_r_est,
        s_w_est: b.s[0] + f * (b.s[1] - b.s[0]),
        s_w: b.s,
        leaves: [ia, ib],
    }
}

impl BroadScratch {
    /// Start a query: the wheel chords of earlier poses become stale.
    fn begin(&mut self, nodes: usize) -> u32 {
        if self.chords.len() != nodes || self.stamp == u32::MAX {
            self.chords.clear();
            self.chords.resize(nodes, (0, WheelChord::default()));
            self.stamp = 0;
        }
        self.stamp += 1;
        self.stamp
    }
}

/// \[-\] how much larger |tan(yaw)| a query with a margin is made for: far more than the
/// margin lets the flange's locus turn (about 0.2 mrad).
const YAW_ALLOWANCE: f64 = 2e-3;

/// The locus curvature factor a query with a margin at `ctx` is made for: that of
/// |tan(yaw)| + `YAW_ALLOWANCE` (at least 1: an unyawed pose may be followed by a yawed one).
fn margin_kappa_scale(pair: &WheelRailPair, ctx: &PoseCtx) -> f64 {
    pair.locus
        .kappa_scale(ctx.tan_yaw.abs() + YAW_ALLOWANCE)
        .max(ctx.kappa_scale)
}

/// The bounding box of the segment `p`–`q`: smallest and largest first, then second component.
#[inline]
fn chord_box(p: [f64; 2], q: [f64; 2]) -> [f64; 4] {
    let (y0, y1) = if p[0] <= q[0] {
        (p[0], q[0])
    } else {
        (q[0], p[0])
    };
    let (z0, z1) = if p[1] <= q[1] {
        (p[1], q[1])
    } else {
        (q[1], p[1])
    };
    [y0, y1, z0, z1]
}

/// A wheel node's chord mapped to the side frame for one pose.
#[derive(Clone, Copy, Debug, Default)]
struct WheelChord {
    /// chord end points on the locus
    q0: [f64; 2],
    q1: [f64; 2],
    /// their bounding box ([`chord_box`])
    bbox: [f64; 4],
    /// \[m\] capsule radius
    thick: f64,
    /// \[m\] chord length (floored at 1e-15)
    len: f64,
}

impl WheelChord {
    fn new(q0: [f64; 2], q1: [f64; 2], thick: f64) -> Self {
        let len = ((q1[0] - q0[0]).powi(2) + (q1[1] - q0[1]).powi(2))
            .sqrt()
            .max(1e-15);
        WheelChord {
            q0,
            q1,
            bbox: chord_box(q0, q1),
            thick,
            len,
        }
    }
}

/// Wheel node `ib`'s chord at the current pose, mapped once per query.
#[inline(always)]
fn mapped<'a>(
    chords: &'a mut [(u32, WheelChord)],
    stamp: u32,
    map: &WheelMap,
    ib: u32,
    b: &TreeNode,
) -> &'a WheelChord {
    let c = &mut chords[ib as usize];
    if c.0 != stamp {
        *c = (stamp, map.chord(b));
    }
    &c.1
}

/// The leaves of the two trees of `pair` that the bounds cannot separate at this pose, in
/// `scratch.candidates` (cleared first). `depth` \[m\] is the deepest interpenetration of
/// interest: arcs further inside the wheel are dropped (the zone edges, where the curves cross,
/// are kept at any depth). With `margin` > 0 \[m\] the result holds for every pose at which no
/// point of the wheel's locus is further than `margin` from where it is at this one
/// ([`BroadMemory`]): the wheel capsules are widened by it and the rules that rest on the
/// directions of the wheel arcs are not applied.
pub(crate) fn candidates(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    depth: f64,
    margin: f64,
    scratch: &mut BroadScratch,
) {
    scratch.candidates.clear();
    let (rt, wt) = (&pair.rail_tree.nodes, &pair.wheel_tree.nodes);
    if rt.is_empty() || wt.is_empty() {
        return;
    }
    let stamp = scratch.begin(wt.len());
    // With a margin the wheel may also yaw a little further before the result is used
    // (`BroadMemory::covers`): the rules hold for the locus curvature up to `YAW_ALLOWANCE`
    // more.
    let kappa_scale = if margin > 0.0 {
        margin_kappa_scale(pair, ctx)
    } else {
        ctx.kappa_scale
    };
    let rules = Rules::new(pair, depth, margin, kappa_scale);
    let (out, chords) = (&mut scratch.candidates, &mut scratch.chords);
    let map = WheelMap::new(pair, ctx);
    let mut stack = [(0u32, 0u32); 96];
    let mut top = 1usize;
    while top > 0 {
        top -= 1;
        let (ia, ib) = stack[top];
        let (a, b) = (&rt[ia as usize], &wt[ib as usize]);
        let w = mapped(chords, stamp, &map, ib, b);
        let Some(o) = overlap(a, b, w, &rules) else {
            continue;
        };
        let (la, lb) = (a.child == 0, b.child == 0);
        if la && lb {
            out.push(estimate(a, b, ia, ib, &o));
            continue;
        }
        // split the longer arc (or the one that is not a leaf)
        let split_a = !la && (lb || a.s[1] - a.s[0] >= b.s[1] - b.s[0]);
        if top + 2 > stack.len() {
            // Cannot happen with trees of depth < 48; keep the pair as a coarse candidate.
            let mut c = estimate(a, b, ia, ib, &o);
            c.leaves = [u32::MAX; 2];
            out.push(c);
            continue;
        }
        // the first child on top: candidates come mostly in the order of the arcs
        if split_a {
            stack[top] = (a.child + 1, ib);
            stack[top + 1] = (a.child, ib);
        } else {
            stack[top] = (ia, b.child + 1);
            stack[top + 1] = (ia, b.child);
        }
        top += 2;
    }
}

/// The pairs of `leaves` (rail and wheel leaf indices, from a query with a margin) that the
/// rules cannot separate at this pose, with their estimates, in `scratch.candidates` (cleared
/// first). Returns `false` (and no candidates) if a pair is not a pair of leaves.
pub(crate) fn recheck(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    depth: f64,
    leaves: &[[u32; 2]],
    scratch: &mut BroadScratch,
) -> bool {
    scratch.candidates.clear();
    let (rt, wt) = (&pair.rail_tree.nodes, &pair.wheel_tree.nodes);
    let stamp = scratch.begin(wt.len());
    let rules = Rules::new(pair, depth, 0.0, ctx.kappa_scale);
    let (out, chords) = (&mut scratch.candidates, &mut scratch.chords);
    let map = WheelMap::new(pair, ctx);
    for &[ia, ib] in leaves {
        let (Some(a), Some(b)) = (rt.get(ia as usize), wt.get(ib as usize)) else {
            out.clear();
            return false;
        };
        let w = mapped(chords, stamp, &map, ib, b);
        if let Some(o) = overlap(a, b, w, &rules) {
            out.push(estimate(a, b, ia, ib, &o));
        }
    }
    true
}

/// What the broad phase keeps of one wheel between the evaluations of a time integration: the
/// leaf pairs of a query with a margin (`candidates`) and the pose it was made at. While no
/// point of the wheel's locus has moved further than the margin (`move_bound`), the rules
/// applied to these pairs alone (`recheck`) keep every leaf pair that can hold an
/// interpenetrating pair (`docs/models/contact.md` §3.2).
#[derive(Clone, Debug, Default)]
pub struct BroadMemory {
    leaves: Vec<[u32; 2]>,
    r: [[f64; 3]; 3],
    c: [f64; 3],
    /// tan yaw as the locus uses it (0 without yaw)
    tan_yaw: f64,
    margin: f64,
    /// the locus curvature factor the query was made for
    kappa_scale: f64,
    valid: bool,
}

impl BroadMemory {
    /// Forget the stored query.
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Whether the stored query covers the pose `ctx`.
    pub(crate) fn covers(&self, pair: &WheelRailPair, ctx: &PoseCtx) -> bool {
        self.valid
            && ctx.kappa_scale <= self.kappa_scale
            && move_bound(pair, self, ctx) <= self.margin
    }

    /// Store the leaf pairs of a query with `margin` made at `ctx` (in `candidates`).
    pub(crate) fn store(
        &mut self,
        pair: &WheelRailPair,
        ctx: &PoseCtx,
        margin: f64,
        candidates: &[Candidate],
    ) {
        self.leaves.clear();
        self.leaves.extend(candidates.iter().map(|c| c.leaves));
        self.r = ctx.r;
        self.c = ctx.c;
        self.tan_yaw = ctx.locus_tan_yaw();
        self.margin = margin;
        self.kappa_scale = margin_kappa_scale(pair, ctx);
        self.valid = true;
    }

    /// The stored leaf pairs.
    pub(crate) fn leaves(&self) -> &[[u32; 2]] {
        &self.leaves
    }
}

/// \[m\] An upper bound of how far any point of the wheel's locus (over the wheel tree's range)
/// lies in the cross-section at the pose `ctx` from where it lay at the pose of `m`.
///
/// A locus point is `P = C + R q` with `q = (rho st, axial, -rho ct)` (`geometry` module docs),
/// `st = clamp(-tan(yaw) rho', ±0.5)` and `ct` its cosine series. For one profile point between
/// the two poses: `ΔP = ΔC + ΔR q_0 + R_1 Δq` with `Δq = (rho Δst, 0, -rho Δct)`. The clamp is
/// 1-Lipschitz, so `|Δst| <= min(S |Δtan|, 1)` with `S` the largest `|rho'|` on the tree (at its
/// nodes, plus 1 %); the
/// series' derivative is at most `1.155 |st|` for `|st| <= 0.5`, so `|Δct| <= 1.155 st_max |Δst|`
/// with `st_max = min(0.5, S max|tan|)`; `|q_0| <= (rho_max min(0.5, S |tan_0|), axial_max,
/// rho_max)` componentwise. Each cross-section component is bounded by the sum of the absolute
/// terms.
pub(crate) fn move_bound(pair: &WheelRailPair, m: &BroadMemory, ctx: &PoseCtx) -> f64 {
    let Some(root) = pair.wheel_tree.nodes.first() else {
        return f64::INFINITY;
    };
    // (the largest |rho'| at the curve's nodes, 1 % added for the curve between them)
    let s = 1.01 * root.slope_abs;
    let rho = root.rho_max;
    let axial = pair.wheel_y0.abs() + root.p0[0].abs().max(root.p1[0].abs()) + root.thick;
    let t1 = ctx.locus_tan_yaw();
    let dt = (t1 - m.tan_yaw).abs();
    let dst = (s * dt).min(1.0);
    let st_max = (s * m.tan_yaw.abs().max(t1.abs())).min(0.5);
    let dct = 1.155 * st_max * dst;
    let q = [rho * (s * m.tan_yaw.abs()).min(0.5), axial, rho];
    let mut d2 = 0.0;
    for i in 1..3 {
        let mut di = (ctx.c[i] - m.c[i]).abs();
        for j in 0..3 {
            di += (ctx.r[i][j] - m.r[i][j]).abs() * q[j];
        }
        di += ctx.r[i][0].abs() * rho * dst + ctx.r[i][2].abs() * rho * dct;
        d2 += di * di;
    }
    d2.sqrt() * (1.0 + 1e-9) + 1e-12
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact_format::manchester_benchmark_pair;
    use crate::geometry::{IsoPair, TravelOptions, locus, travel};
    use crate::pose::{Side, WheelsetPose, WheelsetVelocity};
    use crate::{ContactModelKind, ContactOptions, ContactWorkspace, WheelRailContact};

    /// The benchmark pair, its `polach` contact (to find loaded heights), a 0.1 mm travelling and
    /// a deterministic generator (64-bit LCG, Knuth's constants).
    struct Setup {
        pair: WheelRailPair,
        contact: WheelRailContact,
        fine: TravelOptions,
        ws: ContactWorkspace,
        x: u64,
    }

    impl Setup {
        fn new(seed: u64) -> Self {
            let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
            let pair = manchester_benchmark_pair(&root).unwrap();
            let opts = ContactOptions {
                model: ContactModelKind::Polach,
                ..Default::default()
            };
            Setup {
                contact: WheelRailContact::new(pair.clone(), opts).unwrap(),
                pair,
                fine: TravelOptions {
                    step: 0.1e-3,
                    ..Default::default()
                },
                ws: ContactWorkspace::new(),
                x: seed,
            }
        }

        fn rnd(&mut self, a: f64, b: f64) -> f64 {
            self.x = self
                .x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            a + (b - a) * ((self.x >> 11) as f64 / (1u64 << 53) as f64)
        }

        /// Pose `k`: left and right wheels alternately, over the whole wheel, yaw to 25 mrad,
        /// roll to 15 mrad, pressed up to `press` \[m\] below the height that carries 1 kN;
        /// `None` where that height is not found.
        fn pose(&mut self, k: usize, press: f64) -> Option<(Side, WheelsetPose)> {
            let side = if k.is_multiple_of(2) {
                Side::Left
            } else {
                Side::Right
            };
            let mut pose = WheelsetPose {
                y: self.rnd(-10e-3, 10e-3),
                yaw: self.rnd(-25e-3, 25e-3),
                roll: self.rnd(-15e-3, 15e-3),
                ..Default::default()
            };
            let vel = WheelsetVelocity {
                vx: 30.0,
                spin: -30.0 / 0.46,
                ..Default::default()
            };
            let s = self
                .contact
                .evaluate_with_load(side, &pose, &vel, 1e3, 1e-3, &mut self.ws)
                .ok()?;
            pose.z = s.z - self.rnd(0.0, press);
            Some((side, pose))
        }
    }

    /// Asserts that every pair of `pairs` interpenetrating by less than 0.5 mm lies in one of
    /// `cands` (its rail point in the rail leaf, its wheel point in the wheel leaf); returns
    /// how many were checked and how many of them were deeper than 0.25 mm.
    fn assert_covered(pairs: &[IsoPair], cands: &[Candidate], what: &str) -> (usize, usize) {
        let (mut checked, mut deep) = (0, 0);
        for p in pairs.iter().filter(|p| p.gap < 0.0 && p.gap > -0.5e-3) {
            checked += 1;
            deep += usize::from(p.gap < -0.25e-3);
            assert!(
                cands.iter().any(|c| c.s_r[0] <= p.s_r
                    && p.s_r <= c.s_r[1]
                    && c.s_w[0] <= p.s_w
                    && p.s_w <= c.s_w[1]),
                "{what}: pair at s_r {:.3} mm, s_w {:.3} mm, gap {:.4} mm in no candidate",
                p.s_r * 1e3,
                p.s_w * 1e3,
                p.gap * 1e3
            );
        }
        (checked, deep)
    }

    /// Every interpenetrating pair of a fine travelling (0.1 mm) down to the broad phase's depth
    /// lies in a candidate: its rail point in the candidate's rail leaf and its wheel point in
    /// the candidate's wheel leaf. Poses over the whole wheel, yaw to 25 mrad, roll to 15 mrad,
    /// interpenetration to 0.5 mm.
    #[test]
    fn every_interpenetrating_pair_is_in_a_candidate() {
        let mut t = Setup::new(12345);
        let (mut pairs, mut scratch) = (vec![], BroadScratch::default());
        let (mut checked, mut deep) = (0, 0);
        for k in 0..300 {
            let Some((side, pose)) = t.pose(k, 0.45e-3) else {
                continue;
            };
            let sp = pose.to_side(side);
            travel(&t.pair, &sp, &t.fine, &mut pairs);
            candidates(
                &t.pair,
                &PoseCtx::new(&t.pair, &sp),
                0.5e-3,
                0.0,
                &mut scratch,
            );
            let (c, d) = assert_covered(
                &pairs,
                &scratch.candidates,
                &format!("pose {k} ({side:?} {sp:?})"),
            );
            (checked, deep) = (checked + c, deep + d);
        }
        eprintln!("{checked} pairs, {deep} deep");
        assert!(
            checked > 10_000 && deep > 1000,
            "{checked} pairs, {deep} deep"
        );
    }

    /// A query with a margin made at one pose serves the poses within the margin: for pairs of
    /// poses (the second a random move of the first scaled so that [`move_bound`] is between
    /// 0.3 and 1 times the margin), the bound holds for the locus points of 400 profile points,
    /// and the stored leaf pairs, rechecked at the second pose, hold every interpenetrating pair
    /// of a fine travelling there (as in the test above).
    #[test]
    fn a_query_with_a_margin_serves_the_poses_within_it() {
        let mut t = Setup::new(777);
        let (mut pairs, mut scratch, mut memory) =
            (vec![], BroadScratch::default(), BroadMemory::default());
        let margin = 0.2e-3;
        let root = t.pair.wheel_tree.nodes[0];
        let (s0, s1) = (root.s[0], root.s[1]);
        let (mut checked, mut tight) = (0, 0.0f64);
        for k in 0..300 {
            let Some((side, pose)) = t.pose(k, 0.4e-3) else {
                continue;
            };
            let dir = [
                t.rnd(-1.0, 1.0) * 1e-3,
                t.rnd(-1.0, 1.0) * 1e-3,
                t.rnd(-1.0, 1.0) * 1e-3,
                t.rnd(-1.0, 1.0) * 1e-3,
            ];
            let moved = |f: f64| WheelsetPose {
                y: pose.y + f * dir[0],
                z: pose.z + f * dir[1],
                roll: pose.roll + f * dir[2],
                yaw: pose.yaw + f * dir[3],
            };
            let frac = t.rnd(0.3, 1.0);
            let pair = &t.pair;
            let sp0 = pose.to_side(side);
            let ctx0 = PoseCtx::new(pair, &sp0);
            candidates(pair, &ctx0, 0.5e-3, margin, &mut scratch);
            memory.store(pair, &ctx0, margin, &scratch.candidates);
            let bound_at =
                |f: f64| move_bound(pair, &memory, &PoseCtx::new(pair, &moved(f).to_side(side)));
            let mut f = frac * margin / bound_at(1.0);
            while bound_at(f) > margin {
                f *= 0.9;
            }
            let sp1 = moved(f).to_side(side);
            let ctx1 = PoseCtx::new(pair, &sp1);
            let bound = move_bound(pair, &memory, &ctx1);
            assert!(memory.covers(pair, &ctx1));
            // the bound
            for i in 0..400 {
                let s = s0 + (s1 - s0) * i as f64 / 399.0;
                let (p0, p1) = (locus(pair, &ctx0, s).p, locus(pair, &ctx1, s).p);
                let d = ((p1[1] - p0[1]).powi(2) + (p1[2] - p0[2]).powi(2)).sqrt();
                assert!(
                    d <= bound,
                    "pose {k}: locus point at s {s} moved {d:e} m, bound {bound:e}"
                );
                tight = tight.max(d / bound);
            }
            // the stored pairs, rechecked
            assert!(recheck(pair, &ctx1, 0.5e-3, memory.leaves(), &mut scratch));
            travel(pair, &sp1, &t.fine, &mut pairs);
            let what = format!("pose {k} ({side:?} {sp0:?} moved to {sp1:?})");
            checked += assert_covered(&pairs, &scratch.candidates, &what).0;
        }
        eprintln!("{checked} pairs; largest move / bound {tight:.3}");
        assert!(
            checked > 10_000 && tight > 0.2,
            "{checked} pairs, tightness {tight}"
        );
    }
}
