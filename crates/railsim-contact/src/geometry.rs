//! Contact geometry of one wheel on one rail: the seed's isosceles-pair travelling
//! (Jalili & Salehi 2011, §3.2–3.3) on the wheel's contact locus, and the split of the
//! penetrated zones into patches.
//!
//! Everything here is a pure function of the pair, the side-frame pose and the options; results
//! go into caller-owned buffers so that an evaluation allocates nothing once the buffers have
//! grown to size.
//!
//! # The wheel's contact locus (yaw, exact for a straight rail)
//! A wheel is a surface of revolution. Against a rail that is straight along x, the point of a
//! wheel circle that can touch the rail is the one whose surface normal has no x-component
//! (the normal must lie in the rail's cross-section plane). For the wheel profile point at axial
//! position `Y` with radius `rho(Y)` and the circle angle `theta` measured from the lowest point,
//! the wheelset-frame normal is proportional to `(sin theta, -rho', -cos theta)`; with
//! `R = Rx(roll) Rz(yaw)` its x-component vanishes when `sin theta = -tan(yaw) rho'`. The point
//! `q = (rho sin theta, Y, -rho cos theta)` mapped by the pose is the locus point: its (y, z)
//! form the curve that is paired with the rail, and its x is the longitudinal lead of the contact
//! (several mm ahead of the axle on a yawed flange). This is the "contact locus" idea described
//! by Vollebregt (VSD 60, 2022); the closed form above is derived here. It is exact for a rail
//! straight along x; track curvature under the wheel is neglected (radius ratio ~1e-3).
//!
//! # Regular locus
//! The projected locus turns like the profile, 1/f times faster, with
//! `f = 1 - tan^2(yaw) (rho'^2 + rho rho'')`, and folds where `f = 0` (a cusp; S1002: 33.7 mrad of
//! yaw, at the flange root). A pair accepts yaw only while `f >= 0.2` everywhere, and the
//! curvature bounds of the searches take the locus' curvature, up to
//! `1 / (cos^3(theta) cos^2(yaw) f)` times the profile's (`PoseCtx::kappa_scale`,
//! [`crate::pair::LocusLimits`]).
//!
//! # Isosceles pairs
//! Points A (wheel locus) and B (rail), with unit tangents oriented toward the field side, form
//! an isosceles pair when the chord is perpendicular to the mean tangent:
//! `f = (B - A) . (t_A + t_B) = 0` (contact-theory.md §7.2, equivalent to the seed's equal base
//! angles, eq. 2–4). This form stays regular where the chord vanishes (intersection pairs).
//! Stepping moves both points by the same arc length (seed §3.2 "stepping"); the correction
//! moves the leading point back and the lagging one forward by equal arc lengths (seed eq. 5),
//! computed as a Newton step on `f`. The step is variable: the base step inside and near the
//! penetrated zones, larger outside: the largest step over which the gap cannot fall below half
//! its value given the tangent angle and a curvature bound over the window ahead, and at most
//! 0.8 of the crossing distance CD of seed eq. (1) when the profiles approach each other. Zones
//! resolved by too few pairs are travelled again with a finer step
//! ([`refine_narrow_zones`]).

use crate::error::ContactError;
use crate::pair::WheelRailPair;
use crate::pose::{WheelsetPose, mat_vec, rotation};

/// Options of the travelling algorithm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TravelOptions {
    /// \[m\] arc-length step inside and near penetrated zones (the seed's 0.5 / 0.1 mm)
    pub step: f64,
    /// \[m\] largest step far from contact
    pub max_step: f64,
    /// \[-\] the travelling correction is repeated while the angle error exceeds this (rad)
    pub angle_tol: f64,
    /// \[-\] maximum corrections per step
    pub max_corrections: u32,
}

impl Default for TravelOptions {
    fn default() -> Self {
        TravelOptions {
            step: 1.0e-3,
            max_step: 8.0e-3,
            angle_tol: 1e-5,
            max_corrections: 6,
        }
    }
}

/// \[m\] the travelling steps accepted (`TravelOptions::validate`).
pub const STEP_RANGE: (f64, f64) = (1e-6, 5e-3);

impl TravelOptions {
    /// Check the options.
    pub fn validate(&self) -> Result<(), ContactError> {
        let (lo, hi) = STEP_RANGE;
        if !(self.step.is_finite() && self.step >= lo && self.step <= hi) {
            return Err(ContactError::BadOption {
                key: "step",
                value: format!("{} mm", railsim_profile::short_number(self.step * 1e3)),
                expected: "a travelling step between 0.001 and 5 mm".into(),
            });
        }
        if !(self.max_step.is_finite() && self.max_step >= self.step) {
            return Err(ContactError::BadOption {
                key: "max_step",
                value: format!("{} mm", railsim_profile::short_number(self.max_step * 1e3)),
                expected: "a finite value not smaller than the step".into(),
            });
        }
        Ok(())
    }
}

/// \[m\] gap beyond which travelled pairs are not corrected to full accuracy (they only steer the
/// step; pairs near or inside contact are always exact to `angle_tol`).
pub const FAR_GAP: f64 = 0.3e-3;

/// \[m\] shortest step outside interpenetrated zones.
pub const MIN_STEP: f64 = 0.05e-3;

/// One isosceles pair found by the travelling, in the side frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IsoPair {
    /// \[m\] arc length on the wheel profile curve
    pub s_w: f64,
    /// \[m\] arc length on the (placed) rail curve
    pub s_r: f64,
    /// \[m\] wheel locus point (y, z)
    pub a: [f64; 2],
    /// \[m\] rail point (y, z)
    pub b: [f64; 2],
    /// \[m\] longitudinal position x of the wheel locus point (lead ahead of the axle)
    pub x: f64,
    /// \[m\] signed gap along the pair normal: > 0 separated, < 0 interpenetrating
    pub gap: f64,
    /// unit normal of the pair (perpendicular to the mean tangent), pointing from rail to wheel
    pub n: [f64; 2],
    /// \[-\] cosine of the seed's base angle theta_C (mean of the two base angles' cosines; 0 at
    /// the rigid contact pair, where theta_C = 90 deg)
    pub cos_theta_c: f64,
    /// \[rad\] travelling error |theta_A - theta_B| after one correction (seed Fig. 10);
    /// negative where the chord is too short for the angles to be defined
    pub travel_error: f64,
    /// \[-\] sine of the angle from the rail tangent to the wheel tangent (zero at the rigid pair)
    pub tangent_sin: f64,
    /// \[1/m\] signed curvature of the wheel profile at the pair (the locus curvature without
    /// yaw; see [`locus_curvature_at`] for the yawed locus)
    pub kappa_w: f64,
    /// unit tangent (y, z) of the wheel locus curve at the pair
    pub t_w: [f64; 2],
    /// \[1/m\] signed curvature of the rail curve
    pub kappa_r: f64,
    /// \[m\] wheel radius at the pair (distance from the axle)
    pub rho: f64,
    /// \[-\] wheel profile slope d(rho)/d(axial)
    pub rho_slope: f64,
}

/// Statistics of one travelling.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TravelStats {
    /// Number of pairs recorded.
    pub pairs: u32,
    /// Number of correction iterations in total.
    pub corrections: u32,
    /// Times the pair was lost and re-seeded (a fold of the pair map).
    pub reseeds: u32,
    /// Whether the travelling was warm-started (only windows around the previous contact).
    pub warm: bool,
}

/// Pose quantities used by the locus map.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PoseCtx {
    pub r: [[f64; 3]; 3],
    pub c: [f64; 3],
    pub tan_yaw: f64,
    pub yawed: bool,
    /// factor of the wheel's curvature bounds on the yawed locus
    /// ([`crate::pair::LocusLimits::kappa_scale`]; 1 without yaw)
    pub kappa_scale: f64,
}

impl PoseCtx {
    pub(crate) fn new(pair: &WheelRailPair, pose: &WheelsetPose) -> Self {
        let yawed = pose.yaw.abs() > 1e-12;
        let tan_yaw = pose.yaw.tan();
        PoseCtx {
            r: rotation(pose.roll, pose.yaw),
            c: [0.0, pose.y, pair.r0 + pose.z],
            tan_yaw,
            yawed,
            kappa_scale: pair.locus.kappa_scale(if yawed { tan_yaw } else { 0.0 }),
        }
    }

    /// tan(yaw) as the locus uses it: 0 for a pose [`locus`] treats as unyawed.
    #[inline]
    pub(crate) fn locus_tan_yaw(&self) -> f64 {
        if self.yawed { self.tan_yaw } else { 0.0 }
    }
}

/// The wheel locus evaluated at one profile arc length.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Locus {
    /// side-frame position (x, y, z)
    pub p: [f64; 3],
    /// unit (y, z) tangent of the locus curve
    pub t: [f64; 2],
    /// |d(y,z)/ds_w|: locus arc length per profile arc length
    pub speed: f64,
    pub rho: f64,
    /// unit tangent of the wheel profile (profile frame)
    pub tp: [f64; 2],
    /// profile curvature (equals the locus curvature without yaw)
    pub kappa: f64,
}

impl Locus {
    /// d(rho)/d(axial position): the wheel profile's slope.
    #[inline]
    pub fn rho_slope(&self) -> f64 {
        profile_slope(self.tp)
    }
}

/// The wheel profile's slope d(rho)/d(axial) = -t_z / t_y from its unit tangent `t` (profile
/// frame), |t_y| floored at 1e-6 as in [`locus`].
#[inline]
pub(crate) fn profile_slope(t: [f64; 2]) -> f64 {
    let ty = if t[0].abs() < 1e-6 { 1e-6 } else { t[0] };
    -t[1] / ty
}

/// sin(theta) of the locus point of a wheel circle whose profile slope is `rho_p` (module docs),
/// clamped to 0.5.
#[inline]
pub(crate) fn locus_sin(tan_yaw: f64, rho_p: f64) -> f64 {
    (-tan_yaw * rho_p).clamp(-0.5, 0.5)
}

/// cos(theta) from sin(theta) by the series of sqrt(1 - s²) to s⁶: |sin theta| <= 0.5 (the
/// pair's yaw limit, [`crate::pair::LocusLimits`], keeps |tan(yaw) rho'| below 0.5; the clamp is
/// a guard). Relative error 2.1e-4 at the clamp, 2.9e-6 at 0.3, and 8e-11 at 0.082, the largest
/// |sin theta| of S1002 at its yaw limit (29.9 mrad).
#[inline]
pub(crate) fn locus_cos(st: f64) -> f64 {
    let s2 = st * st;
    1.0 - s2 * (0.5 + s2 * (0.125 + s2 * 0.0625))
}

/// Evaluate the wheel's contact locus at profile arc length `s`.
#[inline]
pub(crate) fn locus(pair: &WheelRailPair, ctx: &PoseCtx, s: f64) -> Locus {
    let cp = pair.wheel.eval(s);
    let (ty, tz) = (cp.t[0], cp.t[1]);
    let axial = pair.wheel_y0 + cp.p[0];
    let rho = pair.r0 - cp.p[1];
    if !ctx.yawed {
        // Without yaw the locus is the profile's lowest line, a rigid image of the profile:
        // P = C + R (0, axial, -rho), tangent R (0, ty, tz), unit speed.
        let r = &ctx.r;
        return Locus {
            p: [
                ctx.c[0] + r[0][1] * axial - r[0][2] * rho,
                ctx.c[1] + r[1][1] * axial - r[1][2] * rho,
                ctx.c[2] + r[2][1] * axial - r[2][2] * rho,
            ],
            t: [r[1][1] * ty + r[1][2] * tz, r[2][1] * ty + r[2][2] * tz],
            speed: 1.0,
            rho,
            tp: [ty, tz],
            kappa: cp.kappa,
        };
    }
    let ty_safe = if ty.abs() < 1e-6 { 1e-6 } else { ty };
    let inv_ty = 1.0 / ty_safe;
    // d(rho)/d(axial) and its derivative, from the profile tangent and curvature.
    let rho_p = -tz * inv_ty;
    let rho_pp = -cp.kappa * inv_ty * inv_ty * inv_ty;
    let st = locus_sin(ctx.tan_yaw, rho_p);
    let ct = locus_cos(st);
    let s2 = st * st;
    let inv_ct = 1.0 + s2 * (0.5 + s2 * (0.375 + s2 * 0.3125));
    let dtheta = -ctx.tan_yaw * rho_pp * inv_ct;
    let q = [rho * st, axial, -rho * ct];
    // dq/d(axial)
    let dq = [
        rho_p * st + rho * ct * dtheta,
        1.0,
        -rho_p * ct + rho * st * dtheta,
    ];
    let pq = mat_vec(&ctx.r, q);
    let d = mat_vec(&ctx.r, dq);
    // d(y,z)/ds_w = d(y,z)/d(axial) * ty
    let (dy, dz) = (d[1] * ty, d[2] * ty);
    let speed = (dy * dy + dz * dz).sqrt().max(1e-12);
    let inv_speed = 1.0 / speed;
    Locus {
        p: [ctx.c[0] + pq[0], ctx.c[1] + pq[1], ctx.c[2] + pq[2]],
        t: [dy * inv_speed, dz * inv_speed],
        speed,
        rho,
        tp: [ty, tz],
        kappa: cp.kappa,
    }
}

/// Signed curvature of the projected locus curve at `s`: the profile curvature without yaw, a
/// central difference of the tangent angle with yaw.
pub(crate) fn locus_curvature(pair: &WheelRailPair, ctx: &PoseCtx, s: f64) -> f64 {
    if !ctx.yawed {
        return locus(pair, ctx, s).kappa;
    }
    let h = 2.0 * pair.wheel.ds();
    let lo = locus(pair, ctx, (s - h).max(0.0));
    let hi = locus(pair, ctx, (s + h).min(pair.wheel.length()));
    let dang = (lo.t[0] * hi.t[1] - lo.t[1] * hi.t[0]).atan2(lo.t[0] * hi.t[0] + lo.t[1] * hi.t[1]);
    let dy = hi.p[1] - lo.p[1];
    let dz = hi.p[2] - lo.p[2];
    let ds = (dy * dy + dz * dz).sqrt().max(1e-12);
    dang / ds
}

/// Signed curvature of the wheel locus at pair `i` from the travelled pairs alone: the profile
/// curvature without yaw; with yaw the change of the locus tangent between the neighbouring pairs
/// over the arc between their wheel points (a central difference on the pairs, no extra curve
/// evaluation).
pub fn locus_curvature_at(pairs: &[IsoPair], i: usize, yawed: bool) -> f64 {
    if !yawed || pairs.len() < 2 {
        return pairs[i].kappa_w;
    }
    let lo = i.saturating_sub(1);
    let hi = (i + 1).min(pairs.len() - 1);
    let (p, q) = (&pairs[lo], &pairs[hi]);
    let (dy, dz) = (q.a[0] - p.a[0], q.a[1] - p.a[1]);
    let ds = (dy * dy + dz * dz).sqrt();
    if ds < 1e-9 {
        return pairs[i].kappa_w;
    }
    (p.t_w[0] * q.t_w[1] - p.t_w[1] * q.t_w[0]) / ds
}

/// Evaluation of a candidate pair.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairEval {
    pub(crate) a: Locus,
    pub(crate) b: railsim_profile::CurvePoint,
    pub(crate) f: f64,
    /// df/de for the symmetric move (wheel +e, rail -e of arc length)
    pub(crate) dfds: f64,
    /// df/de for the wheel point alone moving by +e of locus arc length
    pub(crate) dfdw: f64,
}

#[inline]
pub(crate) fn eval_pair(pair: &WheelRailPair, ctx: &PoseCtx, s_w: f64, s_r: f64) -> PairEval {
    let a = locus(pair, ctx, s_w);
    let b = pair.rail.eval(s_r);
    let d = [b.p[0] - a.p[1], b.p[1] - a.p[2]];
    let ts = [a.t[0] + b.t[0], a.t[1] + b.t[1]];
    let f = d[0] * ts[0] + d[1] * ts[1];
    // Derivative of f for the symmetric move (wheel point forward by +e of locus arc length,
    // rail point back by e), with the curvature terms (dt/ds = kappa * left-normal).
    let na = [-a.t[1], a.t[0]];
    let nb = [-b.t[1], b.t[0]];
    let tab = a.t[0] * b.t[0] + a.t[1] * b.t[1];
    let dfa = -(1.0 + tab) + a.kappa * (d[0] * na[0] + d[1] * na[1]);
    let dfb = (1.0 + tab) + b.kappa * (d[0] * nb[0] + d[1] * nb[1]);
    PairEval {
        a,
        b,
        f,
        dfds: dfa - dfb,
        dfdw: dfa,
    }
}

/// Cosines of the seed's base angles: theta_A between AB and t_A, theta_B between BA and t_B
/// (eq. 2–3), or `None` where the chord is too short for them to be defined.
#[inline]
fn base_cosines(e: &PairEval) -> Option<(f64, f64)> {
    let d = [e.b.p[0] - e.a.p[1], e.b.p[1] - e.a.p[2]];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    // The base angles are undefined where the two points coincide (an intersection pair); below
    // a 1 µm chord they are not reported.
    if len < 1e-6 {
        return None;
    }
    let u = [d[0] / len, d[1] / len];
    let ca = (u[0] * e.a.t[0] + u[1] * e.a.t[1]).clamp(-1.0, 1.0);
    let cb = (-(u[0] * e.b.t[0] + u[1] * e.b.t[1])).clamp(-1.0, 1.0);
    Some((ca, cb))
}

/// The travelling error |theta_A - theta_B| (seed Fig. 10) from the base angles' cosines:
/// `sin(a - b) = sin a cos b - cos a sin b`.
#[inline]
pub(crate) fn travel_error(e: &PairEval) -> f64 {
    match base_cosines(e) {
        Some((ca, cb)) => {
            let (sa, sb) = (
                (1.0 - ca * ca).max(0.0).sqrt(),
                (1.0 - cb * cb).max(0.0).sqrt(),
            );
            (sa * cb - ca * sb).clamp(-1.0, 1.0).asin().abs()
        }
        None => -1.0,
    }
}

/// Apply the seed's correction (eq. 5) as a Newton step on `f`, moving the two points by equal
/// and opposite arc lengths. Returns the new evaluation.
#[inline]
fn correct(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    s_w: &mut f64,
    s_r: &mut f64,
    e: &PairEval,
) -> PairEval {
    let mut de = -e.f / e.dfds;
    // A step larger than a few mm means the pair map folds here; cap it.
    de = de.clamp(-2e-3, 2e-3);
    *s_w = (*s_w + de / e.a.speed).clamp(0.0, pair.wheel.length());
    *s_r = (*s_r - de).clamp(0.0, pair.rail.length());
    eval_pair(pair, ctx, *s_w, *s_r)
}

/// Find the wheel arc length whose locus pairs with the rail point at `s_r`: a first guess from
/// the rigid placement of the profile (roll about the axle, yaw neglected), Newton on the locus
/// y, then Newton on f moving the wheel point only.
fn seed_wheel(pair: &WheelRailPair, ctx: &PoseCtx, s_r: f64, s_lo: f64) -> f64 {
    let yb = pair.rail.eval(s_r).p[0];
    let (l_w, _) = (pair.wheel.length(), ());
    // y of a profile point ~ C_y + cos(roll) * axial + sin(roll) * rho (R row 1, yaw neglected)
    let (sf, cf) = (ctx.r[2][1], ctx.r[1][1]);
    let axial = (yb - ctx.c[1] - sf * pair.r0) / cf.max(0.5);
    let mut s_w = pair
        .wheel
        .s_at_y(axial - pair.wheel_y0)
        .unwrap_or(if axial - pair.wheel_y0 < pair.wheel.y_range().0 {
            s_lo
        } else {
            l_w
        })
        .clamp(s_lo, l_w);
    for _ in 0..4 {
        let a = locus(pair, ctx, s_w);
        let dy = a.t[0] * a.speed;
        if dy.abs() < 1e-3 {
            break;
        }
        let step = ((yb - a.p[1]) / dy).clamp(-2e-3, 2e-3);
        s_w = (s_w + step).clamp(s_lo, l_w);
        if step.abs() < 1e-10 {
            break;
        }
    }
    for _ in 0..8 {
        let a = locus(pair, ctx, s_w);
        let b = pair.rail.eval(s_r);
        let d = [b.p[0] - a.p[1], b.p[1] - a.p[2]];
        let ts = [a.t[0] + b.t[0], a.t[1] + b.t[1]];
        let f = d[0] * ts[0] + d[1] * ts[1];
        let df = -a.speed * (1.0 + a.t[0] * b.t[0] + a.t[1] * b.t[1]);
        let step = (-f / df).clamp(-2e-3, 2e-3);
        s_w = (s_w + step).clamp(s_lo, l_w);
        if step.abs() < 1e-12 {
            break;
        }
    }
    s_w
}

/// The isosceles pair whose rail point is at arc length `s_r` (rail-anchored pairs, used near
/// contact so that the pairs sit at pose-independent rail positions): Newton on f moving the wheel
/// point only, from the guess `s_w`. A guess already within a tenth of the angle tolerance is kept.
/// Returns the pair, its wheel arc length and the travelling error after the first correction
/// (-1 where not defined); re-seeds the wheel point if Newton fails.
pub(crate) fn pair_at_rail(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    opts: &TravelOptions,
    s_r: f64,
    s_w: f64,
    stats: &mut TravelStats,
) -> (PairEval, f64, f64) {
    let l_w = pair.wheel.length();
    let mut s_w = s_w.clamp(0.0, l_w);
    let mut e = eval_pair(pair, ctx, s_w, s_r);
    let mut err = -1.0;
    let chord_of =
        |e: &PairEval| ((e.b.p[0] - e.a.p[1]).powi(2) + (e.b.p[1] - e.a.p[2]).powi(2)).sqrt();
    if e.f.abs() <= 0.1 * opts.angle_tol * chord_of(&e).max(1e-9) {
        return (e, s_w, travel_error(&e));
    }
    for k in 0..opts.max_corrections {
        let de = (-e.f / e.dfdw).clamp(-2e-3, 2e-3);
        s_w = (s_w + de / e.a.speed).clamp(0.0, l_w);
        e = eval_pair(pair, ctx, s_w, s_r);
        stats.corrections += 1;
        if k == 0 {
            err = if e.f.abs() < 1e-3 {
                travel_error(&e)
            } else {
                -1.0
            };
        }
        if e.f.abs() <= opts.angle_tol * chord_of(&e).max(1e-9) {
            return (e, s_w, err);
        }
    }
    // Lost (a fold of the pair map): re-seed the wheel point from the rail point.
    s_w = seed_wheel(pair, ctx, s_r, pair.wheel_s_tip);
    stats.reseeds += 1;
    let e = eval_pair(pair, ctx, s_w, s_r);
    (e, s_w, -1.0)
}

pub(crate) fn record(e: &PairEval, s_w: f64, s_r: f64, travel_error: f64) -> IsoPair {
    let (n, gap) = normal_and_gap(e);
    let cos_theta_c = match base_cosines(e) {
        Some((ca, cb)) => 0.5 * (ca + cb),
        None => 0.0,
    };
    let tangent_sin = e.b.t[0] * e.a.t[1] - e.b.t[1] * e.a.t[0];
    IsoPair {
        s_w,
        s_r,
        a: [e.a.p[1], e.a.p[2]],
        b: e.b.p,
        x: e.a.p[0],
        gap,
        n,
        cos_theta_c,
        travel_error,
        tangent_sin,
        kappa_w: e.a.kappa,
        t_w: e.a.t,
        kappa_r: e.b.kappa,
        rho: e.a.rho,
        rho_slope: e.a.rho_slope(),
    }
}

/// Travel along both profiles from the flange tip to the field side and record every isosceles
/// pair in `out` (cleared first). `pose` is in the side frame.
///
/// Far from contact the seed's stepping (equal arcs, symmetric correction, variable step with
/// the tried longer steps); once the gap falls below [`ANCHOR_GAP`] the pairs are rail-anchored at
/// the nodes of the base step's grid (see `docs/models/contact.md` §3): the run starts two nodes
/// before the pair that found the low gap (dropping the far pairs recorded there) and ends at the
/// second consecutive node whose gap is above it again. Every zone therefore has at least two
/// anchored pairs on each side, at pose-independent positions, whatever the far stepping did: the
/// pairs a patch uses (the zone and two neighbours on each side) are the same as those of a warm
/// start that travels only windows around the previous contact (`crate::warm`).
pub fn travel(
    pair: &WheelRailPair,
    pose: &WheelsetPose,
    opts: &TravelOptions,
    out: &mut Vec<IsoPair>,
) -> TravelStats {
    out.clear();
    let ctx = PoseCtx::new(pair, pose);
    let mut stats = TravelStats::default();
    // Start on the rail at the lateral position of the wheel's flange tip.
    let y_tip = locus(pair, &ctx, pair.wheel_s_tip).p[1];
    let mut s_r = pair.rail.s_at_y(y_tip).unwrap_or(0.0);
    let mut s_w = seed_wheel(pair, &ctx, s_r, pair.wheel_s_tip);
    let mut e = eval_pair(pair, &ctx, s_w, s_r);
    for _ in 0..opts.max_corrections {
        if e.f.abs() < 1e-13 {
            break;
        }
        e = correct(pair, &ctx, &mut s_w, &mut s_r, &e);
    }
    let mut prev_gap: Option<(f64, f64)> = None;
    let mut err = -1.0;
    let mut slope: Option<f64> = None;
    // last node of the previous anchored run
    let mut last_run_end: Option<i64> = None;
    loop {
        let mut rec = record(&e, s_w, s_r, err);
        if rec.gap <= ANCHOR_GAP {
            // Near contact: an anchored run from two nodes before this pair, or continuing the
            // previous run where the two would meet.
            let hs = opts.step;
            let mut k0 = ((s_r / hs + 1e-9).floor() as i64 - 2).max(0);
            if let Some(k_e) = last_run_end
                && k0 <= k_e + 1
            {
                k0 = k_e;
            }
            let s0 = k0 as f64 * hs;
            let guess = interpolate_s_w(out, s0, |p| (p.s_r, p.s_w))
                .unwrap_or(s_w + (s0 - s_r) / e.a.speed);
            while out.last().is_some_and(|p| p.s_r >= s0 - 1e-12) {
                out.pop();
                stats.pairs -= 1;
            }
            match anchored_run(pair, &ctx, opts, k0, guess, RunEnd::Clear, out, &mut stats) {
                None => break,
                Some(run) => {
                    (e, s_w, s_r, slope) = (run.e, run.s_w, run.s_r, run.slope);
                    prev_gap = Some((run.g_prev, hs));
                    last_run_end = Some(run.k);
                    rec = *out.last().expect("an anchored run records its first node");
                }
            }
        } else {
            out.push(rec);
            stats.pairs += 1;
        }
        let g = rec.gap;
        // Step size: base step near contact, larger outside (never past a possible zone).
        let mut h = opts.step;
        // kappa bound and curvature-safe step, when the base step was tried instead (below)
        let mut fallback: Option<(f64, f64)> = None;
        if g > 0.0 {
            // No zone can be skipped: over a step D the gap falls by at most
            // |g'| D + kappa_b D^2 / 2, with g' the angle between the tangents (the gap's slope
            // per unit arc) and kappa_b a bound on the relative curvature over the window ahead;
            // the step keeps half of the gap.
            let kb = kb_at(pair, &ctx, s_w, s_r);
            let gp = rec.tangent_sin.abs();
            let mut cand = (-gp + (gp * gp + kb * g).sqrt()) / kb;
            if let Some((g0, ds0)) = prev_gap
                && g < g0
                && ds0 > 0.0
            {
                // Approaching an intersection: the seed's crossing distance (eq. 1).
                let chord = ((e.b.p[0] - e.a.p[1]).powi(2) + (e.b.p[1] - e.a.p[2]).powi(2)).sqrt();
                let cos_c = rec.cos_theta_c.abs().max(1e-12);
                let cd = chord / (2.0 * cos_c);
                cand = cand.min(0.8 * cd);
            }
            // The base step is not a floor here: near a zone the safe step may be shorter, so
            // that no zone narrower than the base step is skipped (a small floor keeps progress).
            h = cand.clamp(opts.step.min(MIN_STEP), opts.max_step);
            // Try a longer step first: the base step where the safe step is shorter (near a
            // zone edge), twice the safe step elsewhere (far from contact). It is kept when no
            // zone can hide between the two pairs, i.e. with |g''| <= kb the gap stays above
            // min(g0, g1) - kb h^2 / 8 > 0, or, for the base step only, when it lands in a zone
            // (whose edge then lies within one base step, the resolution inside zones).
            // Otherwise the travelling steps back and takes the safe step. This avoids crawling
            // toward every zone edge and halves the pairs far from contact.
            let h_try = if h < opts.step {
                opts.step
            } else {
                (2.0 * h).min(opts.max_step)
            };
            if h_try > h {
                fallback = Some((kb, h));
                h = h_try;
            }
        }
        prev_gap = Some((g, h));
        let (s_w0, s_r0) = (s_w, s_r);
        let exact = g <= FAR_GAP;
        let step_by = |h: f64, s_w: &mut f64, s_r: &mut f64, stats: &mut TravelStats| {
            advance(pair, &ctx, opts, s_w, s_r, &e, h, exact, slope, stats)
        };
        let mut stepped = step_by(h, &mut s_w, &mut s_r, &mut stats);
        if let (Some((kb, h_safe)), Some((next, _))) = (fallback, &stepped) {
            let g1 = normal_and_gap(next).1;
            let keep = if g1 > 0.0 {
                g.min(g1) > 0.125 * kb * h * h
            } else {
                h <= opts.step
            };
            if !keep {
                (s_w, s_r) = (s_w0, s_r0);
                prev_gap = Some((g, h_safe));
                stepped = step_by(h_safe, &mut s_w, &mut s_r, &mut stats);
            }
        }
        match stepped {
            Some((next, next_err)) => {
                // secant of the pair curve, for the next predictor (only between exact pairs)
                slope = (g <= FAR_GAP && next_err >= 0.0 && s_r > s_r0)
                    .then(|| (s_w - s_w0) / (s_r - s_r0));
                e = next;
                err = next_err;
            }
            None => break,
        }
    }
    stats
}

/// The wheel arc length at rail arc length `s_r`, interpolated linearly between the two items
/// of `items` (sorted by rail arc length; `at` gives an item's rail and wheel arc lengths) that
/// bracket it; `None` outside them.
pub(crate) fn interpolate_s_w<T>(
    items: &[T],
    s_r: f64,
    at: impl Fn(&T) -> (f64, f64),
) -> Option<f64> {
    let j = items.partition_point(|p| at(p).0 <= s_r);
    if j == 0 || j == items.len() {
        return None;
    }
    let ((r0, w0), (r1, w1)) = (at(&items[j - 1]), at(&items[j]));
    let f = (s_r - r0) / (r1 - r0).max(1e-15);
    Some(w0 + f * (w1 - w0))
}

/// How an anchored run ends.
#[derive(Clone, Copy, Debug)]
pub(crate) enum RunEnd {
    /// After the second consecutive node whose gap is above [`ANCHOR_GAP`] (cold travelling).
    Clear,
    /// At the node of this index (the windows of a warm start).
    At(i64),
}

/// The last pair of an anchored run, from which the travelling goes on.
pub(crate) struct RunState {
    e: PairEval,
    s_w: f64,
    s_r: f64,
    slope: Option<f64>,
    /// gap of the node before the last one
    g_prev: f64,
    /// index of the last node
    k: i64,
}

/// Rail-anchored pairs at the nodes `k * step` of the rail, from node `k0` (wheel arc length
/// guess `guess`) until `end`, with the dyadic midpoints where a zone could hide between two
/// nodes ([`subdivide`]); pushed to `out` in travelling order. `None` when a profile's end was
/// reached (the travelling ends there).
#[allow(clippy::too_many_arguments)]
pub(crate) fn anchored_run(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    opts: &TravelOptions,
    k0: i64,
    guess: f64,
    end: RunEnd,
    out: &mut Vec<IsoPair>,
    stats: &mut TravelStats,
) -> Option<RunState> {
    let hs = opts.step;
    let (l_r, l_w) = (pair.rail.length(), pair.wheel.length());
    let mut k = k0;
    let mut s_r = k as f64 * hs;
    if s_r >= l_r {
        return None;
    }
    let (mut e, mut s_w, err) = pair_at_rail(pair, ctx, opts, s_r, guess, stats);
    if s_w >= l_w {
        return None;
    }
    out.push(record(&e, s_w, s_r, err));
    stats.pairs += 1;
    let mut g = normal_and_gap(&e).1;
    let mut g_prev = f64::NEG_INFINITY;
    let mut slope: Option<f64> = None;
    loop {
        let done = match end {
            RunEnd::Clear => g > ANCHOR_GAP && g_prev > ANCHOR_GAP,
            RunEnd::At(k_end) => k >= k_end,
        };
        if done {
            return Some(RunState {
                e,
                s_w,
                s_r,
                slope,
                g_prev,
                k,
            });
        }
        let s_next = (k + 1) as f64 * hs;
        if s_next >= l_r {
            return None;
        }
        let equal = 1.0 / e.a.speed;
        let ratio = match slope {
            Some(q) if q > 0.5 * equal && q < 2.0 * equal => q,
            _ => equal,
        };
        let (e1, s_w1, err1) =
            pair_at_rail(pair, ctx, opts, s_next, s_w + ratio * (s_next - s_r), stats);
        if s_w1 >= l_w {
            return None;
        }
        let g1 = normal_and_gap(&e1).1;
        if g > 0.0 && g1 > 0.0 {
            let kb = kb_at(pair, ctx, s_w, s_r);
            subdivide(
                pair,
                ctx,
                opts,
                (s_r, s_w, g),
                (s_next, s_w1, g1),
                kb,
                2,
                out,
                stats,
            );
        }
        slope = Some((s_w1 - s_w) / (s_next - s_r));
        out.push(record(&e1, s_w1, s_next, err1));
        stats.pairs += 1;
        (g_prev, g) = (g, g1);
        (e, s_w, s_r) = (e1, s_w1, s_next);
        k += 1;
    }
}

/// \[m\] gap below which the pairs are rail-anchored: small enough that the grid covers only the
/// neighbourhood of the zones (a larger value costs pairs on conformal approaches), large enough
/// that a zone's neighbours on both sides are grid nodes.
pub const ANCHOR_GAP: f64 = 0.03e-3;

/// Rail-anchored pairs between two pairs `lo` and `hi` (rail arc length, wheel arc length, gap),
/// both with a positive gap, at the dyadic midpoints where a zone could hide between them
/// (min gap <= kb h^2 / 8), to `depth` halvings; pushed to `out` in travelling order.
#[allow(clippy::too_many_arguments)]
fn subdivide(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    opts: &TravelOptions,
    lo: (f64, f64, f64),
    hi: (f64, f64, f64),
    kb: f64,
    depth: u32,
    out: &mut Vec<IsoPair>,
    stats: &mut TravelStats,
) {
    let h = hi.0 - lo.0;
    if depth == 0 || lo.2.min(hi.2) > 0.125 * kb * h * h {
        return;
    }
    let s_r = 0.5 * (lo.0 + hi.0);
    let (e, s_w, err) = pair_at_rail(pair, ctx, opts, s_r, 0.5 * (lo.1 + hi.1), stats);
    let g = normal_and_gap(&e).1;
    let mid = (s_r, s_w, g);
    if g > 0.0 {
        subdivide(pair, ctx, opts, lo, mid, kb, depth - 1, out, stats);
    }
    out.push(record(&e, s_w, s_r, err));
    stats.pairs += 1;
    if g > 0.0 {
        subdivide(pair, ctx, opts, mid, hi, kb, depth - 1, out, stats);
    }
}

/// \[1/m\] bound on the relative curvature of the rail and the wheel's locus over the window
/// ahead (at least 1).
pub(crate) fn kb_at(pair: &WheelRailPair, ctx: &PoseCtx, s_w: f64, s_r: f64) -> f64 {
    pair.kappa_bound(s_w, s_r, ctx.kappa_scale).max(1.0)
}

/// The pair's normal (from the mean of the two tangents) and its signed gap \[m\] along it.
pub(crate) fn normal_and_gap(e: &PairEval) -> ([f64; 2], f64) {
    let mut tm = [e.a.t[0] + e.b.t[0], e.a.t[1] + e.b.t[1]];
    let l = (tm[0] * tm[0] + tm[1] * tm[1]).sqrt().max(1e-300);
    tm = [tm[0] / l, tm[1] / l];
    let n = [-tm[1], tm[0]];
    (
        n,
        (e.a.p[1] - e.b.p[0]) * n[0] + (e.a.p[2] - e.b.p[1]) * n[1],
    )
}

/// One step of the travelling from the evaluated pair `e` at (`s_w`, `s_r`) by the arc `h`:
/// stepping by equal arcs (seed §3.2), one correction (eq. 5 as a Newton step) whose residual is
/// the travelling error, further corrections to `angle_tol` when `exact`, and a re-seed if the
/// pair was lost. Returns the new pair and its travelling error, or `None` past a curve's end.
#[allow(clippy::too_many_arguments)]
fn advance(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    opts: &TravelOptions,
    s_w: &mut f64,
    s_r: &mut f64,
    e: &PairEval,
    h: f64,
    exact: bool,
    slope: Option<f64>,
    stats: &mut TravelStats,
) -> Option<(PairEval, f64)> {
    // Predictor: equal arcs on both curves (the seed's stepping), or the secant of the last two
    // pairs (`slope` = ds_w/ds_r) where it is close to it, which leaves less to correct.
    let equal = 1.0 / e.a.speed;
    let ratio = match slope {
        Some(k) if k > 0.5 * equal && k < 2.0 * equal => k,
        _ => equal,
    };
    let s_w_new = *s_w + h * ratio;
    let s_r_new = *s_r + h;
    if s_w_new >= pair.wheel.length() || s_r_new >= pair.rail.length() {
        return None;
    }
    *s_w = s_w_new;
    *s_r = s_r_new;
    let mut e = eval_pair(pair, ctx, *s_w, *s_r);
    // Far from contact the pairs only steer the step size: a pair within 0.05 rad of isosceles
    // measures the gap to a relative error below 0.1 %, so it is corrected only that far. Near
    // contact the pairs are corrected to `angle_tol`; a predicted pair already within a tenth of
    // it is kept as it is.
    let tol = if exact { 0.1 * opts.angle_tol } else { 0.05 };
    let chord = ((e.b.p[0] - e.a.p[1]).powi(2) + (e.b.p[1] - e.a.p[2]).powi(2)).sqrt();
    if e.f.abs() <= tol * chord.max(1e-9) {
        let err = if exact { travel_error(&e) } else { -1.0 };
        return Some((e, err));
    }
    let tol = if exact { opts.angle_tol } else { 0.05 };
    e = correct(pair, ctx, s_w, s_r, &e);
    stats.corrections += 1;
    // The travelling error is a diagnostic of the pairs near contact (seed Fig. 10).
    let err = if e.f.abs() < 1e-3 {
        travel_error(&e)
    } else {
        -1.0
    };
    let mut k = 1;
    while k < opts.max_corrections {
        let chord = ((e.b.p[0] - e.a.p[1]).powi(2) + (e.b.p[1] - e.a.p[2]).powi(2)).sqrt();
        if e.f.abs() <= tol * chord.max(1e-9) {
            break;
        }
        e = correct(pair, ctx, s_w, s_r, &e);
        stats.corrections += 1;
        k += 1;
    }
    let s_r_min = s_r_new - 0.75 * h;
    if k == opts.max_corrections || *s_r < s_r_min {
        // Lost the pair (a fold of the pair map), or the correction undid the step: re-seed
        // from the stepped rail point, so that the travelling always moves forward.
        *s_r = s_r.max(s_r_min);
        *s_w = seed_wheel(pair, ctx, *s_r, pair.wheel_s_tip);
        e = eval_pair(pair, ctx, *s_w, *s_r);
        stats.reseeds += 1;
    }
    Some((e, err))
}

/// How many pairs resolve a zone, and the indices of the pairs bounding them: the zone's pairs,
/// or with `loaded` (STRIPES) only those inside its contact, where the
/// interpenetration exceeds `(1 - eps0) delta0` (seed eq. 7–9; `eps0` from the Hertz
/// coefficients of the deepest pair's profile curvatures): a flange zone is often much wider
/// than the strip of it that carries load.
fn resolution(pairs: &[IsoPair], z: &Zone, loaded: bool) -> (usize, usize, usize) {
    let bounds = |a: usize, b: usize| {
        let i0 = a.saturating_sub(1);
        let i1 = (b + 1).min(pairs.len() - 1);
        (b + 1 - a, i0, i1)
    };
    if !loaded {
        return bounds(z.first, z.last);
    }
    let p = &pairs[z.deepest];
    let a = crate::patch::longitudinal_curvature(p.rho, p.rho_slope);
    let b = (0.5 * (p.kappa_w - p.kappa_r)).max(crate::patch::B_MIN);
    let eps = railsim_elastic::stripes_epsilon(&railsim_elastic::hertz_coeffs_fast(a, b), a, b);
    let threshold = (1.0 - eps) * -p.gap;
    let inside = |i: &usize| -pairs[*i].gap > threshold;
    match (
        (z.first..=z.last).find(inside),
        (z.first..=z.last).rev().find(inside),
    ) {
        (Some(a), Some(b)) => bounds(a, b),
        _ => bounds(z.first, z.last),
    }
}

/// Re-travel every zone resolved by fewer than `min_pairs` pairs (`resolution`: its pairs, or
/// with `loaded` those in its contact) with a step that gives it `min_pairs`, so that narrow
/// patches (flange root, flange) are resolved whatever the base step. The refined pairs replace
/// the zone's pairs; `scratch` is reused as the new list. Returns whether anything changed (the
/// zones must then be found again).
#[allow(clippy::too_many_arguments)]
pub fn refine_narrow_zones(
    pair: &WheelRailPair,
    pose: &WheelsetPose,
    opts: &TravelOptions,
    min_pairs: usize,
    loaded: bool,
    pairs: &mut Vec<IsoPair>,
    zones: &[Zone],
    scratch: &mut Vec<IsoPair>,
    stats: &mut TravelStats,
) -> bool {
    // (the pose context and the new list only once a zone needs refining)
    let mut ctx: Option<PoseCtx> = None;
    let mut next = 0;
    for z in zones {
        let (count, i0, i1) = resolution(pairs, z, loaded);
        if count >= min_pairs {
            continue;
        }
        let ctx = ctx.get_or_insert_with(|| {
            scratch.clear();
            PoseCtx::new(pair, pose)
        });
        // zones are ordered and disjoint: at most the shared neighbour was written already
        debug_assert!(i0 + 1 >= next, "zones out of order");
        scratch.extend_from_slice(&pairs[next..=i0]);
        // Rail-anchored pairs on the grid of step/n, n the smallest integer that gives the
        // resolved part of the zone (with its two neighbours) at least `min_pairs` pairs: the
        // positions stay independent of the pose for a given n, as in the travelling. Only that
        // part is re-travelled (with `loaded`, the pairs outside the contact bound its edges and
        // carry no load).
        let (s_a, s_b) = (pairs[i0].s_r, pairs[i1].s_r);
        let n = ((min_pairs + 1) as f64 * opts.step / (s_b - s_a).max(1e-9))
            .ceil()
            .clamp(1.0, 1e4);
        let h = opts.step / n;
        // Two zones split from one run share a neighbour, which the first zone's refinement has
        // already passed: start after the last pair written.
        let (mut s_w, mut s_r) = match scratch.last() {
            Some(p) if p.s_r > s_a => (p.s_w, p.s_r),
            _ => (pairs[i0].s_w, s_a),
        };
        let mut slope = 1.0;
        let mut s_next = ((s_r / h + 1e-9).floor() + 1.0) * h;
        while s_next < s_b - 0.25 * h {
            let (e, s_w1, err) =
                pair_at_rail(pair, ctx, opts, s_next, s_w + slope * (s_next - s_r), stats);
            scratch.push(record(&e, s_w1, s_next, err));
            stats.pairs += 1;
            slope = (s_w1 - s_w) / (s_next - s_r);
            (s_w, s_r) = (s_w1, s_next);
            s_next += h;
        }
        next = i1;
    }
    if ctx.is_none() {
        return false;
    }
    scratch.extend_from_slice(&pairs[next..]);
    std::mem::swap(pairs, scratch);
    true
}

/// One patch: a run of consecutive interpenetrating pairs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Zone {
    /// index of the first interpenetrating pair
    pub first: usize,
    /// index of the last interpenetrating pair
    pub last: usize,
    /// index of the deepest pair
    pub deepest: usize,
    /// \[-\] the part of its solution the zone carries (`crate::wells`: a well of the Hertz
    /// models or STRIPES; 1 for the half-space model, which solves whole zones)
    pub share: f64,
}

/// Split the travelled pairs into penetrated zones (patches).
///
/// Rule: every maximal run of consecutive pairs with negative gap is a zone. Inside a run, two
/// penetration maxima are split into separate patches at the minimum between them when the
/// minimum is below `split_depth_ratio` of the smaller maximum and the contact angles at the
/// two maxima differ by more than `split_angle`. Zones are never merged: STRIPES has no elastic
/// coupling between patches, so two zones separated by a positive gap are two patches.
pub fn find_zones(
    pairs: &[IsoPair],
    split_angle: f64,
    split_depth_ratio: f64,
    zones: &mut Vec<Zone>,
) {
    zones.clear();
    for (first, last) in interpenetrating_runs(pairs) {
        split_run(pairs, first, last, split_angle, split_depth_ratio, zones);
    }
}

/// The maximal runs of consecutive interpenetrating pairs (negative gap), as (first, last).
pub(crate) fn interpenetrating_runs(pairs: &[IsoPair]) -> impl Iterator<Item = (usize, usize)> {
    let mut i = 0;
    std::iter::from_fn(move || {
        while i < pairs.len() && pairs[i].gap >= 0.0 {
            i += 1;
        }
        if i == pairs.len() {
            return None;
        }
        let first = i;
        while i + 1 < pairs.len() && pairs[i + 1].gap < 0.0 {
            i += 1;
        }
        i += 1;
        Some((first, i - 1))
    })
}

/// The maximal run of interpenetrating pairs that holds the pairs `a..=b` (themselves
/// interpenetrating), as (first, last).
pub(crate) fn run_around(pairs: &[IsoPair], a: usize, b: usize) -> (usize, usize) {
    let (mut first, mut last) = (a, b);
    while first > 0 && pairs[first - 1].gap < 0.0 {
        first -= 1;
    }
    while last + 1 < pairs.len() && pairs[last + 1].gap < 0.0 {
        last += 1;
    }
    (first, last)
}

fn deepest(pairs: &[IsoPair], first: usize, last: usize) -> usize {
    let mut k = first;
    for j in first..=last {
        if pairs[j].gap < pairs[k].gap {
            k = j;
        }
    }
    k
}

fn split_run(
    pairs: &[IsoPair],
    first: usize,
    last: usize,
    split_angle: f64,
    ratio: f64,
    zones: &mut Vec<Zone>,
) {
    let angle = |p: &IsoPair| p.n[0].atan2(p.n[1]);
    let mut prev_min: Option<usize> = None;
    for j in first..=last {
        let left_ok = j == first || pairs[j].gap <= pairs[j - 1].gap;
        let right_ok = j == last || pairs[j].gap < pairs[j + 1].gap;
        if !(left_ok && right_ok) {
            continue;
        }
        if let Some(a) = prev_min {
            let mut m = a;
            for k in a..=j {
                if pairs[k].gap > pairs[m].gap {
                    m = k;
                }
            }
            let pen_small = (-pairs[a].gap).min(-pairs[j].gap);
            if m > a
                && m < j
                && -pairs[m].gap < ratio * pen_small
                && (angle(&pairs[a]) - angle(&pairs[j])).abs() > split_angle
            {
                split_run(pairs, first, m, split_angle, ratio, zones);
                split_run(pairs, m + 1, last, split_angle, ratio, zones);
                return;
            }
            if pairs[j].gap < pairs[a].gap {
                prev_min = Some(j);
            }
        } else {
            prev_min = Some(j);
        }
    }
    zones.push(Zone {
        first,
        last,
        deepest: deepest(pairs, first, last),
        share: 1.0,
    });
}
