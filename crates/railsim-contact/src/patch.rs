//! From a penetrated zone of isosceles pairs to a patch: the rigid contact pair, the patch
//! frame, and the per-strip data used by the normal and tangential models.

use crate::geometry::{IsoPair, PoseCtx, Zone, locus_curvature};
use crate::pair::WheelRailPair;
use crate::pose::{WheelsetVelocity, cross, dot3, mat_vec};
use railsim_elastic::Creepages;

/// \[1/m\] smallest lateral relative curvature used in Hertz formulas; concave (conformal) spots
/// are clamped to it (CONTACT's KPEC/ANALYN floor of 1e-4 1/mm, contact-theory.md §1.2).
pub const B_MIN: f64 = 0.1;

/// \[rad\] the contact angle of a contact normal `n` (y, z in the side frame, from rail to
/// wheel): the rotation from the track's z axis to it, positive when it leans toward the flange
/// ([`PatchFrame::contact_angle`]).
#[inline]
pub fn contact_angle_of(n: [f64; 2]) -> f64 {
    (-n[0]).atan2(n[1])
}

/// The rigid contact pair of a patch and the patch's planar frame, in the side frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchFrame {
    /// \[m\] reference point on the rail (y, z), side frame: the rail point of the rigid pair
    pub rail_point: [f64; 2],
    /// \[m\] reference point on the wheel (x, y, z), side frame: the wheel locus point
    pub wheel_point: [f64; 3],
    /// \[m\] arc length of the reference on the wheel profile curve
    pub s_w: f64,
    /// unit normal (y, z) from rail to wheel
    pub n: [f64; 2],
    /// unit lateral tangent (y, z) toward the field side
    pub t: [f64; 2],
    /// \[rad\] contact angle: rotation from the track z-axis to the normal, positive when the
    /// normal leans toward the gauge side (toward the flange)
    pub contact_angle: f64,
    /// \[m\] largest interpenetration of the undeformed surfaces (the seed's delta_0)
    pub delta0: f64,
    /// \[1/m\] longitudinal relative curvature A at the reference (half the sum of curvatures)
    pub a_curv: f64,
    /// \[1/m\] lateral relative curvature B at the reference, clamped to [`B_MIN`]
    pub b_curv: f64,
    /// \[m\] wheel radius at the reference
    pub rho: f64,
    /// \[-\] index of the deepest pair within the travelled pairs
    pub deepest: usize,
}

impl PatchFrame {
    /// Midpoint (y, z) between the rail and wheel points of the rigid pair.
    pub fn midpoint(&self) -> [f64; 2] {
        [
            0.5 * (self.rail_point[0] + self.wheel_point[1]),
            0.5 * (self.rail_point[1] + self.wheel_point[2]),
        ]
    }

    /// \[m\] lateral coordinate in the patch plane of a pair's midpoint, from the rigid pair.
    pub fn lateral(&self, p: &IsoPair) -> f64 {
        let (m, m0) = (mid(p), self.midpoint());
        (m[0] - m0[0]) * self.t[0] + (m[1] - m0[1]) * self.t[1]
    }

    /// \[m\] a pair's interpenetration measured along the patch normal: `-gap / cos Δγ`, `Δγ`
    /// the angle between the pair's normal and the patch's (cosine floored at 0.5). Two
    /// surfaces that are locally parallel, `d` apart along their common normal and tilted by
    /// `Δγ` from the plane, are `d / cos Δγ` apart along the plane's normal at one lateral
    /// coordinate (the lateral offset of the two ends of the chord `d n` adds `d sin²Δγ / cos Δγ`
    /// to its component `d cos Δγ`). It is the undeformed distance a planar half-space problem
    /// takes (`contact-theory.md` §4, the gap along the normal of the contact plane).
    pub fn normal_interpenetration(&self, p: &IsoPair) -> f64 {
        let c = p.n[0] * self.n[0] + p.n[1] * self.n[1];
        -p.gap / c.max(0.5)
    }
}

/// Longitudinal relative curvature of a wheel point (Meusnier: the normal section along the
/// rolling direction of a surface of revolution has curvature cos(beta)/rho, beta the angle
/// between surface normal and radius; the straight rail adds nothing). Half the sum, Hertz's A.
#[inline]
pub fn longitudinal_curvature(rho: f64, rho_slope: f64) -> f64 {
    0.5 / (rho * (1.0 + rho_slope * rho_slope).sqrt())
}

/// Midpoint of a pair.
#[inline]
pub(crate) fn mid(p: &IsoPair) -> [f64; 2] {
    [0.5 * (p.a[0] + p.b[0]), 0.5 * (p.a[1] + p.b[1])]
}

/// The vertex of the parabola through pair `k` and its two neighbours, in the lateral
/// coordinate along pair `k`'s tangent: `(frac, toward_next, delta0)`, the vertex's fraction of
/// the way to the neighbour on its side, whether that is `k + 1`, and the interpenetration
/// there. `None` where `k` has no neighbour on either side, the neighbours do not lie on either
/// side of it along the tangent (extreme poses), or the parabola is not concave with its vertex
/// at least as deep as pair `k`.
fn vertex(pairs: &[IsoPair], k: usize) -> Option<(f64, bool, f64)> {
    if k == 0 || k + 1 >= pairs.len() {
        return None;
    }
    let p = &pairs[k];
    let t = [p.n[1], -p.n[0]];
    let m0 = mid(&pairs[k - 1]);
    let m1 = mid(p);
    let m2 = mid(&pairs[k + 1]);
    let x0 = (m0[0] - m1[0]) * t[0] + (m0[1] - m1[1]) * t[1];
    let x2 = (m2[0] - m1[0]) * t[0] + (m2[1] - m1[1]) * t[1];
    let (y0, y1, y2) = (-pairs[k - 1].gap, -p.gap, -pairs[k + 1].gap);
    // Parabola through (x0,y0), (0,y1), (x2,y2).
    let d = x0 * x2 * (x0 - x2);
    if !(x0 < 0.0 && x2 > 0.0 && d.abs() > 1e-30) {
        return None;
    }
    let a = (x2 * (y0 - y1) - x0 * (y2 - y1)) / d;
    let b = (x0 * x0 * (y2 - y1) - x2 * x2 * (y0 - y1)) / d;
    if a >= 0.0 {
        return None;
    }
    let xv = (-b / (2.0 * a)).clamp(x0, x2);
    let yv = y1 + b * xv + a * xv * xv;
    if yv < y1 {
        return None;
    }
    let toward_next = xv >= 0.0;
    let frac = if toward_next { xv / x2 } else { xv / x0 };
    Some((frac, toward_next, yv))
}

/// Locate the rigid contact pair of a zone: the seed's theta_C = 90 deg point, which is where
/// the interpenetration is largest. With `refine` (travelled pairs) refined by a parabola
/// through the deepest pair and its neighbours (in the lateral coordinate along the mean
/// tangent); the point search's pairs are exact minima, and its neighbours other wells.
///
/// The neighbour on the vertex's side gives a second estimate from its own parabola, weighted
/// by the vertex's fraction of the way to it: 0 at the deepest pair, 1/2 midway, where the two
/// pairs are equally deep and both parabolas put the vertex (equal values at two points put a
/// parabola's vertex midway between them). So the frame and the interpenetration move
/// continuously when the deepest pair passes to the neighbour. Taken from the deepest pair's
/// parabola alone they jumped there by the two parabolas' difference: on a flange patch of the
/// elastic-rail curve (59 kN) the normal force by 19 N, 3e-4 of it (docs/models/contact.md §4).
pub(crate) fn patch_frame(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    pairs: &[IsoPair],
    zone: &Zone,
    refine: bool,
) -> PatchFrame {
    let k = zone.deepest;
    let p = &pairs[k];
    // the reference as a fraction `frac` of the way from pair k to pair j
    let (mut j, mut frac, mut delta0) = (k, 0.0, -p.gap);
    if refine && let Some((f, toward_next, yv)) = vertex(pairs, k) {
        delta0 = yv;
        if f > 0.0 {
            j = if toward_next { k + 1 } else { k - 1 };
            frac = f;
            if let Some((fj, next_j, yj)) = vertex(pairs, j) {
                // the neighbour's vertex as a fraction from k (on its far side: at j)
                let toward_k = next_j == (k > j);
                let from_k = if toward_k { 1.0 - fj } else { 1.0 };
                let w = f;
                frac = (1.0 - w) * f + w * from_k;
                delta0 = (1.0 - w) * yv + w * yj;
            }
        }
    }
    let q = if j != k {
        lerp_pair(p, &pairs[j], frac)
    } else {
        *p
    };
    let n = normalize2(q.n);
    let t = [n[1], -n[0]];
    let rho = q.rho;
    let a_curv = longitudinal_curvature(rho, q.rho_slope);
    let kw = locus_curvature(pair, ctx, q.s_w);
    let b_curv = (0.5 * (kw - q.kappa_r)).max(B_MIN);
    PatchFrame {
        rail_point: q.b,
        wheel_point: [q.x, q.a[0], q.a[1]],
        s_w: q.s_w,
        n,
        t,
        contact_angle: contact_angle_of(n),
        delta0,
        a_curv,
        b_curv,
        rho,
        deepest: k,
    }
}

#[inline]
fn normalize2(v: [f64; 2]) -> [f64; 2] {
    let l = (v[0] * v[0] + v[1] * v[1]).sqrt().max(1e-300);
    [v[0] / l, v[1] / l]
}

/// Linear interpolation between two pairs.
pub(crate) fn lerp_pair(p: &IsoPair, q: &IsoPair, f: f64) -> IsoPair {
    let l = |a: f64, b: f64| a + f * (b - a);
    IsoPair {
        s_w: l(p.s_w, q.s_w),
        s_r: l(p.s_r, q.s_r),
        a: [l(p.a[0], q.a[0]), l(p.a[1], q.a[1])],
        b: [l(p.b[0], q.b[0]), l(p.b[1], q.b[1])],
        x: l(p.x, q.x),
        gap: l(p.gap, q.gap),
        n: [l(p.n[0], q.n[0]), l(p.n[1], q.n[1])],
        cos_theta_c: l(p.cos_theta_c, q.cos_theta_c),
        travel_error: p.travel_error.max(q.travel_error),
        tangent_sin: l(p.tangent_sin, q.tangent_sin),
        kappa_w: l(p.kappa_w, q.kappa_w),
        t_w: [l(p.t_w[0], q.t_w[0]), l(p.t_w[1], q.t_w[1])],
        kappa_r: l(p.kappa_r, q.kappa_r),
        rho: l(p.rho, q.rho),
        rho_slope: l(p.rho_slope, q.rho_slope),
    }
}

/// Rigid-body kinematics of the wheel in the side frame, for creepages.
#[derive(Clone, Copy, Debug)]
pub struct WheelKinematics {
    /// \[m\] axle centre
    pub c: [f64; 3],
    /// \[m/s\] axle centre velocity
    pub v_c: [f64; 3],
    /// \[rad/s\] angular velocity
    pub omega: [f64; 3],
    /// \[m/s\] reference speed dividing the creepages (the rolling speed)
    pub v_ref: f64,
}

impl WheelKinematics {
    pub(crate) fn new(ctx: &PoseCtx, roll: f64, vel: &WheelsetVelocity) -> Self {
        let axle = mat_vec(&ctx.r, [0.0, 1.0, 0.0]);
        let (sf, cf) = roll.sin_cos();
        let zr = [0.0, -sf, cf];
        let omega = [
            vel.spin * axle[0] + vel.roll_rate + vel.yaw_rate * zr[0],
            vel.spin * axle[1] + vel.yaw_rate * zr[1],
            vel.spin * axle[2] + vel.yaw_rate * zr[2],
        ];
        WheelKinematics {
            c: ctx.c,
            v_c: [vel.vx, vel.vy, vel.vz],
            omega,
            v_ref: vel.vx,
        }
    }

    /// Creepages of the wheel relative to the rail at wheel point `p` (side frame), in the patch
    /// axes x (track), `t` (lateral in the plane) and the normal `n` (spin); Kalker's convention
    /// (contact-theory.md §3.1): creepage = slip velocity of the wheel over the rail / speed.
    pub fn creepages(&self, p: [f64; 3], t: [f64; 2], n: [f64; 2]) -> Creepages {
        let r = [p[0] - self.c[0], p[1] - self.c[1], p[2] - self.c[2]];
        let w = cross(self.omega, r);
        let v = [self.v_c[0] + w[0], self.v_c[1] + w[1], self.v_c[2] + w[2]];
        Creepages {
            xi: v[0] / self.v_ref,
            eta: (v[1] * t[0] + v[2] * t[1]) / self.v_ref,
            phi: dot3(self.omega, [0.0, n[0], n[1]]) / self.v_ref,
        }
    }
}

/// The patch reference point: the centroid of the interpenetration over the zone, weighted by
/// `d^(5/2)` per unit lateral length (`d` the interpenetration of each pair), and the contact
/// angle as the same weighted mean of the pair normals' angles. This is the rule of CONTACT's
/// planar contact approach (D = 2: the integral over x of the squared interpenetration of a
/// parabolic gap, `(16/15) d^2 sqrt(2 r d)`, Vollebregt, VSD 60, 2022), so that positions and
/// angles compare like for like. Unlike the deepest point, it is stable on wide, flat (conformal)
/// tread patches where the interpenetration has two shallow maxima.
///
/// Returns the interpolated pair at the reference and the contact angle (positive toward the
/// flange).
pub fn reference_point(pairs: &[IsoPair], zone: &Zone) -> (IsoPair, f64) {
    let lat = |p: &IsoPair| {
        let m = mid(p);
        // lateral coordinate along the deepest pair's tangent
        let d = &pairs[zone.deepest];
        let t = [d.n[1], -d.n[0]];
        let m0 = mid(d);
        (m[0] - m0[0]) * t[0] + (m[1] - m0[1]) * t[1]
    };
    let mut sw = 0.0;
    let mut sl = 0.0;
    let mut sa = 0.0;
    for i in zone.first..=zone.last {
        let p = &pairs[i];
        let d = (-p.gap).max(0.0);
        let lo = if i > 0 { lat(&pairs[i - 1]) } else { lat(p) };
        let hi = if i + 1 < pairs.len() {
            lat(&pairs[i + 1])
        } else {
            lat(p)
        };
        let w = d * d * d.sqrt() * 0.5 * (hi - lo).abs();
        sw += w;
        sl += w * lat(p);
        sa += w * (-p.n[0]).atan2(p.n[1]);
    }
    if sw <= 0.0 {
        let p = pairs[zone.deepest];
        return (p, (-p.n[0]).atan2(p.n[1]));
    }
    let lc = sl / sw;
    let angle = sa / sw;
    // Interpolate the pair at the centroid's lateral coordinate.
    let mut k = zone.first;
    while k < zone.last && lat(&pairs[k + 1]) < lc {
        k += 1;
    }
    let (la, lb) = (lat(&pairs[k]), lat(&pairs[(k + 1).min(zone.last)]));
    let f = if (lb - la).abs() > 1e-15 {
        ((lc - la) / (lb - la)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (
        lerp_pair(&pairs[k], &pairs[(k + 1).min(zone.last)], f),
        angle,
    )
}

/// A patch's normal force `fn_` and lateral force `fs`, given along the normal and tangent of a
/// plane at contact angle `plane_angle`, expressed along the normal and tangent of the patch
/// frame at `frame_angle` (both angles as `PatchFrame::contact_angle`): a rotation by their
/// difference `d` in the cross-section, `n_plane = n cos d - t sin d` and
/// `t_plane = t cos d + n sin d`. Returns `(fn_, fs)` in the frame's axes.
pub fn from_plane_to_frame(fn_: f64, fs: f64, plane_angle: f64, frame_angle: f64) -> (f64, f64) {
    let (sd, cd) = (plane_angle - frame_angle).sin_cos();
    (fn_ * cd + fs * sd, fs * cd - fn_ * sd)
}

/// \[N·m\] A patch's spin moment moved from one point to another: `mz` about the normal at the
/// first point, the patch force `fx` (along the track) and `fs` (along the patch tangent `t`),
/// the second point `dx` along the track and `dl` along `t` from the first. The moment about
/// the second point along the normal is `mz + ((r - r_ref) × F)·n = mz + dl·fx - dx·fs` for the
/// right-handed patch axes (x, t, n), `(e_x × t)·n = 1` (rigid-body statics; the normal force
/// and the moments about x and t are not part of a patch's reported spin moment).
pub fn spin_moment_moved(mz: f64, fx: f64, fs: f64, dx: f64, dl: f64) -> f64 {
    mz + dl * fx - dx * fs
}

#[cfg(test)]
mod moved_tests {
    use super::{PatchFrame, from_plane_to_frame, mid, spin_moment_moved};
    use crate::geometry::IsoPair;

    /// Two parallel surfaces (lines in the cross-section) `d` apart along their normal, tilted
    /// by `γ` from a patch plane: the interpenetration a planar half-space problem takes at the
    /// lateral coordinate of a pair's midpoint is their distance along the plane's normal
    /// there, `d / cos γ` (the old `d cos γ` was 1.5 % low in force on a conformal flange root).
    #[test]
    fn a_tilted_pair_interpenetrates_by_the_distance_along_the_plane_normal() {
        let frame = PatchFrame {
            n: [0.0, 1.0],
            t: [1.0, 0.0],
            ..Default::default()
        };
        for (gamma, d) in [(0.3f64, 50e-6), (-0.2, 20e-6), (0.0, 10e-6)] {
            let (sg, cg) = gamma.sin_cos();
            let (n, t) = ([-sg, cg], [cg, sg]);
            // rail line through b with normal n; the wheel's line d further *into* the rail
            let b = [1e-3 + 2e-3 * t[0], 2e-3 * t[1]];
            let a = [b[0] - d * n[0], b[1] - d * n[1]];
            let pair = IsoPair {
                a,
                b,
                n,
                gap: -d,
                ..Default::default()
            };
            // the two lines' heights at the midpoint's lateral coordinate
            let l = mid(&pair)[0];
            let height = |p: [f64; 2]| p[1] + (l - p[0]) * t[1] / t[0];
            let along_normal = height(b) - height(a);
            let got = frame.normal_interpenetration(&pair);
            assert!(
                (got - along_normal).abs() < 1e-12 * d.max(1.0),
                "γ {gamma}: {got} against {along_normal}"
            );
        }
    }

    /// The force given along one plane's normal and tangent is the same vector along the
    /// frame's (n = (−sin δ, cos δ), t = (cos δ, sin δ) in the cross-section, as the patch
    /// frame's), for both signs of the planes' difference.
    #[test]
    fn a_force_in_the_reference_plane_is_the_same_vector_in_the_frame() {
        let axes = |a: f64| {
            let (s, c) = a.sin_cos();
            ([-s, c], [c, s])
        };
        for (plane, frame) in [(-0.0568, -0.0460), (0.31, 0.29), (1.2, 1.22), (0.0, 0.0)] {
            let (fn_p, fs_p) = (9870.0, -2579.0);
            let (fn_f, fs_f) = from_plane_to_frame(fn_p, fs_p, plane, frame);
            let ((np, tp), (nf, tf)) = (axes(plane), axes(frame));
            for k in 0..2 {
                let want = fn_p * np[k] + fs_p * tp[k];
                let got = fn_f * nf[k] + fs_f * tf[k];
                assert!(
                    (got - want).abs() < 1e-9,
                    "{plane} {frame}: {got} vs {want}"
                );
            }
        }
    }
    use crate::pose::{cross, dot3};

    /// Against the cross product in three dimensions, for patch tangents at several contact
    /// angles and both signs of every offset and force.
    #[test]
    fn the_moved_spin_moment_is_the_cross_product_about_the_new_point() {
        for (k, angle) in [-1.2f64, -0.3, 0.0, 0.4, 1.22].into_iter().enumerate() {
            let (sa, ca) = angle.sin_cos();
            // patch axes in (x, y, z): x along the track, t and n in the cross-section
            let (t, n) = ([0.0, ca, sa], [0.0, -sa, ca]);
            assert!((dot3(cross([1.0, 0.0, 0.0], t), n) - 1.0).abs() < 1e-15);
            let sgn = if k % 2 == 0 { 1.0 } else { -1.0 };
            let (fx, fs, fnn, mz) = (1200.0 * sgn, -3400.0, 6e4, 17.0 * sgn);
            let (dx, dl) = (-2.7e-3 * sgn, 0.8e-3);
            let f: [f64; 3] =
                std::array::from_fn(|i| fx * [1.0, 0.0, 0.0][i] + fs * t[i] + fnn * n[i]);
            // r - r_ref: minus the offset of the new point
            let r: [f64; 3] = std::array::from_fn(|i| -(dx * [1.0, 0.0, 0.0][i] + dl * t[i]));
            let expected = mz + dot3(cross(r, f), n);
            let got = spin_moment_moved(mz, fx, fs, dx, dl);
            assert!(
                (got - expected).abs() < 1e-9,
                "{angle}: {got} vs {expected}"
            );
        }
    }
}
