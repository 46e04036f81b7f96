//! The immutable description of one wheel/rail pair: profiles, their placement, material and
//! friction. Built once from a [`PairSpec`]; shared by every evaluation.

use railsim_elastic::{KalkerTable, Material};
use railsim_profile::{ArcCurve, Profile, RailPlacement, place_rail};

use crate::broad::ArcTree;
use crate::error::ContactError;
use crate::friction::Friction;

/// What a [`WheelRailPair`] is built from. Lengths in metres.
#[derive(Clone, Debug)]
pub struct PairSpec {
    /// Wheel profile in its profile frame (y toward the field side, z up, y = 0 on the
    /// measuring circle).
    pub wheel: Profile,
    /// Rail profile in its profile frame (y toward the field side, z up).
    pub rail: Profile,
    /// \[m\] nominal rolling radius r0 (radius at the wheel profile's z = 0)
    pub r0: f64,
    /// \[m\] distance between the flange backs of the two wheels (1360 mm)
    pub flange_back_distance: f64,
    /// \[m\] profile y-coordinate of the flange back (-70 mm for S1002)
    pub flange_back_y: f64,
    /// \[m\] track gauge, measured `gauge_depth` below the top of the rails (1435 mm)
    pub gauge: f64,
    /// \[m\] depth below the rail top at which the gauge is measured (14 mm)
    pub gauge_depth: f64,
    /// \[rad\] rail inclination toward the track centre applied to the rail profile
    /// (atan(1/40)); 0 for a profile file that is already inclined
    pub inclination: f64,
    /// Combined elastic constants of wheel and rail.
    pub material: Material,
    /// Coulomb friction coefficient, constant or varying with the contact angle
    pub friction: Friction,
    /// \[m\] sampling step of the arc-length curves built from the profiles
    pub curve_ds: f64,
    /// \[-\] smoothing parameter of the profile splines (0 = interpolating)
    pub smoothing: f64,
}

/// One wheel/rail pair, ready for evaluation. Geometry is held in the *side frame* (see
/// [`crate::pose`]): the rail curve is placed there; the wheel curve is kept in its profile frame
/// and mapped by the wheelset pose at each evaluation.
#[derive(Clone, Debug)]
pub struct WheelRailPair {
    /// Wheel profile as an arc-length curve, profile frame.
    pub wheel: ArcCurve,
    /// Rail profile as an arc-length curve, already placed in the side frame.
    pub rail: ArcCurve,
    /// Where the rail profile's origin went in the side frame.
    pub rail_placement: RailPlacement,
    /// \[m\] axial distance from the wheelset centre to the wheel profile's y = 0
    pub wheel_y0: f64,
    /// \[m\] nominal rolling radius
    pub r0: f64,
    /// \[m\] arc length on the wheel curve of the flange tip (lowest point); travelling starts there
    pub wheel_s_tip: f64,
    /// Combined elastic constants.
    pub material: Material,
    /// Kalker's creep coefficients at the material's Poisson ratio (`KalkerTable`), for the
    /// strips' ellipses of STRIPES
    pub kalker: KalkerTable,
    /// Coulomb friction coefficient, constant or varying with the contact angle
    pub friction: Friction,
    /// \[1/m\] largest |curvature| of the wheel curve within [`KAPPA_WINDOW`] ahead of each node
    /// (index `floor(s / ds)`), for the far-field step control of the travelling
    pub wheel_kappa_ahead: Vec<f64>,
    /// \[1/m\] the same for the rail curve
    pub rail_kappa_ahead: Vec<f64>,
    wheel_inv_ds: f64,
    rail_inv_ds: f64,
    /// Bounding hierarchy of the wheel curve from the flange tip on (the part that is travelled),
    /// for the single-point search of the Hertz models (`crate::broad`).
    pub wheel_tree: ArcTree,
    /// Bounding hierarchy of the rail curve.
    pub rail_tree: ArcTree,
    /// \[1/m\] largest |curvature| of the wheel curve
    pub wheel_kappa_max: f64,
    /// \[1/m\] largest |curvature| of the rail curve
    pub rail_kappa_max: f64,
    /// How far the wheel can be yawed before its contact locus folds.
    pub locus: LocusLimits,
}

/// The yaw angles the wheel's contact locus supports (`crate::geometry` module docs, "regular
/// locus").
///
/// With `T = tan(yaw)`, the locus point of the profile point at axial position `Y` is
/// `q = (rho sin(theta), Y, -rho cos(theta))`, `sin(theta) = -T rho'`, and its projection on
/// the cross-section has the derivative `dq/dY = f (cos(yaw), -rho' / cos(theta))` (after the
/// yaw; the roll turns the cross-section rigidly) with `f = 1 - T^2 (rho'^2 + rho rho'')`. The
/// locus is a regular curve, turning the same way as the profile, while `f > 0` everywhere, i.e.
/// `T^2 K < 1` with `K` the largest `rho'^2 + rho rho''` over the travelled profile; where
/// `f = 0` it has a cusp (for the S1002 wheel at the flange root, where `rho rho''` reaches
/// about 880, at 33.7 mrad of yaw), beyond which the projected outline of the wheel is the
/// envelope of a folded locus, which the 2-D search does not model. Its curvature is
/// `cos(yaw) |rho''| / (cos^3(theta) f (cos^2(yaw) + rho'^2 / cos^2(theta))^(3/2))`, at most
/// `1 / (cos^3(theta) cos^2(yaw) f)` times the profile's `|rho''| / (1 + rho'^2)^(3/2)`:
/// [`crate::geometry`] scales the wheel's curvature bounds by that factor
/// ([`LocusLimits::kappa_scale`]). Derived here from the locus of Vollebregt (VSD 60, 2022).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocusLimits {
    /// \[-\] largest `rho'^2 + rho rho''` over the travelled profile (from the flange tip), at
    /// the curve's nodes and midway between them, plus 2 % (0 if negative everywhere)
    pub k: f64,
    /// \[-\] largest `|rho'|` there, plus 2 %
    pub slope_max: f64,
    /// \[-\] largest accepted `|tan(yaw)|`: `f >= LOCUS_MIN_SPEED` everywhere and
    /// `|sin(theta)| <= 0.5` (the clamp of [`crate::geometry`] never acts), at most tan(0.2 rad)
    pub tan_yaw_max: f64,
}

/// \[-\] smallest locus speed factor `f` (see [`LocusLimits`]) of an accepted yaw: the locus'
/// curvature is then at most five times the profile's (S1002: |yaw| <= 29 mrad).
pub const LOCUS_MIN_SPEED: f64 = 0.2;

impl LocusLimits {
    /// The limits of `wheel` (profile frame, nominal radius `r0`) from arc length `s0` on.
    pub fn new(wheel: &ArcCurve, s0: f64, r0: f64) -> Self {
        let h = 0.5 * wheel.ds();
        let n = ((wheel.length() - s0) / h).ceil() as usize;
        let (mut k, mut slope) = (0.0f64, 0.0f64);
        for i in 0..=n {
            let c = wheel.eval((s0 + i as f64 * h).min(wheel.length()));
            let ty = if c.t[0].abs() < 1e-6 { 1e-6 } else { c.t[0] };
            // rho = r0 - z, rho' = -t_z / t_y, rho'' = -kappa / t_y^3 (profile-frame curvature)
            let rho_p = -c.t[1] / ty;
            let rho_pp = -c.kappa / (ty * ty * ty);
            k = k.max(rho_p * rho_p + (r0 - c.p[1]) * rho_pp);
            slope = slope.max(rho_p.abs());
        }
        let (k, slope_max) = (1.02 * k, 1.02 * slope);
        let by_speed = if k > 0.0 {
            ((1.0 - LOCUS_MIN_SPEED) / k).sqrt()
        } else {
            f64::INFINITY
        };
        let by_clamp = if slope_max > 0.0 {
            0.5 / slope_max
        } else {
            f64::INFINITY
        };
        LocusLimits {
            k,
            slope_max,
            tan_yaw_max: by_speed.min(by_clamp).min(0.2f64.tan()),
        }
    }

    /// The factor by which the locus' curvature can exceed the profile's at `tan_yaw` (at most
    /// `1 / LOCUS_MIN_SPEED / cos^3(30°)` within the accepted yaw); 1 without yaw.
    pub fn kappa_scale(&self, tan_yaw: f64) -> f64 {
        if tan_yaw == 0.0 {
            return 1.0;
        }
        let t2 = tan_yaw * tan_yaw;
        let f = (1.0 - t2 * self.k).max(LOCUS_MIN_SPEED);
        let st = (tan_yaw.abs() * self.slope_max).min(0.5);
        let c2 = 1.0 - st * st;
        // 1 / cos^2(yaw) = 1 + tan^2(yaw)
        (1.0 + t2) / (c2 * c2.sqrt() * f)
    }
}

/// \[m\] length of the window over which curvature bounds are taken ahead of a point; at least
/// the largest travelling step.
pub const KAPPA_WINDOW: f64 = 10e-3;

/// Largest |curvature| within `KAPPA_WINDOW` ahead of each node of a curve (and one node behind,
/// so that a bound holds between nodes).
fn kappa_ahead(c: &ArcCurve) -> Vec<f64> {
    let ds = c.ds();
    let n = (c.length() / ds).round() as usize + 1;
    let k: Vec<f64> = (0..n)
        .map(|i| c.eval((i as f64 * ds).min(c.length())).kappa.abs())
        .collect();
    let w = (KAPPA_WINDOW / ds).ceil() as usize;
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(1);
            let hi = (i + w).min(n - 1);
            k[lo..=hi].iter().fold(0.0f64, |a, &b| a.max(b))
        })
        .collect()
}

impl WheelRailPair {
    /// \[1/m\] bound on the relative curvature of the pair over the window ahead of (s_w, s_r),
    /// the wheel's part scaled by `wheel_scale` (the yawed locus' [`LocusLimits::kappa_scale`]).
    #[inline]
    pub fn kappa_bound(&self, s_w: f64, s_r: f64, wheel_scale: f64) -> f64 {
        let [w, r] = self.kappa_ahead(s_w, s_r);
        wheel_scale * w + r
    }

    /// \[1/m\] the bounds on the wheel profile's and the rail's curvature over the window ahead
    /// of (s_w, s_r).
    #[inline]
    pub fn kappa_ahead(&self, s_w: f64, s_r: f64) -> [f64; 2] {
        let iw = ((s_w * self.wheel_inv_ds) as usize).min(self.wheel_kappa_ahead.len() - 1);
        let ir = ((s_r * self.rail_inv_ds) as usize).min(self.rail_kappa_ahead.len() - 1);
        [self.wheel_kappa_ahead[iw], self.rail_kappa_ahead[ir]]
    }
}

/// \[m\] plausible nominal wheel radii r0 (`WheelRailPair::new` refuses others).
pub const R0_RANGE: (f64, f64) = (0.1, 1.0);
/// \[m\] plausible flange-back distances.
pub const FLANGE_BACK_DISTANCE_RANGE: (f64, f64) = (0.5, 2.0);
/// \[m\] plausible profile coordinates of the flange back.
pub const FLANGE_BACK_Y_RANGE: (f64, f64) = (-0.2, 0.2);
/// \[m\] plausible track gauges.
pub const GAUGE_RANGE: (f64, f64) = (0.6, 2.0);

impl WheelRailPair {
    /// Build the pair: splines, arc-length curves and the rail placement.
    pub fn new(spec: &PairSpec) -> Result<Self, ContactError> {
        // Plausible ranges (the vehicle and track files check the same quantities): beyond them
        // a value is a unit or data error, and an infinite or huge one would size the searches'
        // grids and trees.
        for (what, v, lo, hi, expected) in [
            (
                "r0",
                spec.r0,
                R0_RANGE.0,
                R0_RANGE.1,
                "a wheel radius from 0.1 to 1 m",
            ),
            (
                "flange_back_distance",
                spec.flange_back_distance,
                FLANGE_BACK_DISTANCE_RANGE.0,
                FLANGE_BACK_DISTANCE_RANGE.1,
                "a flange-back distance from 0.5 to 2 m",
            ),
            (
                "flange_back_y",
                spec.flange_back_y,
                FLANGE_BACK_Y_RANGE.0,
                FLANGE_BACK_Y_RANGE.1,
                "the flange back's profile coordinate, within ±0.2 m",
            ),
            (
                "gauge",
                spec.gauge,
                GAUGE_RANGE.0,
                GAUGE_RANGE.1,
                "a track gauge from 0.6 to 2 m",
            ),
            (
                "gauge_depth",
                spec.gauge_depth,
                1e-3,
                0.03,
                "a gauge measuring depth from 1 to 30 mm below the rail top",
            ),
            (
                "inclination",
                spec.inclination,
                -0.2,
                0.2,
                "a rail inclination within ±0.2 rad (1:5)",
            ),
            (
                "curve_ds",
                spec.curve_ds,
                1e-6,
                1e-3,
                "a curve spacing from 0.001 to 1 mm",
            ),
        ] {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                let unit = if what == "inclination" { "rad" } else { "m" };
                return Err(ContactError::BadOption {
                    key: what,
                    value: format!("{} {unit}", railsim_profile::short_number(v)),
                    expected: expected.into(),
                });
            }
        }
        spec.friction.check()?;
        let wheel = ArcCurve::from_profile(&spec.wheel, spec.smoothing, spec.curve_ds)?;
        let (placed, rail_placement) =
            place_rail(&spec.rail, spec.inclination, spec.gauge, spec.gauge_depth)?;
        let rail = ArcCurve::from_profile(&placed, spec.smoothing, spec.curve_ds)?;
        // Travelling starts at the flange tip (the lowest point on the gauge side of the
        // measuring circle), so that the flange back, which faces away from the rail, is never
        // paired; a profile without a flange (tip less than 5 mm below the measuring circle) is
        // travelled from its gauge-side end.
        let n = (wheel.length() / spec.curve_ds).ceil() as usize;
        let mut s_tip = 0.0;
        let mut z_min = f64::INFINITY;
        let z_ref = spec.wheel.z_at(0.0).unwrap_or(0.0);
        for i in 0..=n {
            let s = (i as f64 * spec.curve_ds).min(wheel.length());
            let c = wheel.eval(s);
            if c.p[0] < 0.0 && c.p[1] < z_min {
                z_min = c.p[1];
                s_tip = s;
            }
        }
        if z_min > z_ref - 5e-3 {
            s_tip = 0.0;
        }
        let wheel_kappa_ahead = kappa_ahead(&wheel);
        let wheel_inv_ds = 1.0 / wheel.ds();
        let rail_inv_ds = 1.0 / rail.ds();
        let rail_kappa_ahead = kappa_ahead(&rail);
        let largest = |k: &[f64]| k.iter().fold(0.0f64, |m, &x| m.max(x));
        let (wheel_kappa_max, rail_kappa_max) =
            (largest(&wheel_kappa_ahead), largest(&rail_kappa_ahead));
        let locus = LocusLimits::new(&wheel, s_tip, spec.r0);
        let wheel_tree = ArcTree::new(&wheel, s_tip, wheel.length(), spec.r0);
        let rail_tree = ArcTree::new(&rail, 0.0, rail.length(), 0.0);
        Ok(WheelRailPair {
            wheel,
            rail,
            rail_placement,
            wheel_y0: 0.5 * spec.flange_back_distance - spec.flange_back_y,
            r0: spec.r0,
            wheel_s_tip: s_tip,
            material: spec.material,
            kalker: KalkerTable::new(spec.material.nu)?,
            friction: spec.friction.clone(),
            wheel_kappa_ahead,
            rail_kappa_ahead,
            wheel_inv_ds,
            rail_inv_ds,
            wheel_tree,
            rail_tree,
            wheel_kappa_max,
            rail_kappa_max,
            locus,
        })
    }

    /// Rail-profile lateral coordinate (field positive) of a side-frame point.
    pub fn rail_profile_y(&self, y_side: f64, z_side: f64) -> f64 {
        let (s, c) = (-self.rail_placement.rotation).sin_cos();
        let dy = y_side - self.rail_placement.y_origin;
        let dz = z_side - self.rail_placement.z_origin;
        c * dy - s * dz
    }
}

#[cfg(test)]
mod tests {
    use crate::contact_format::manchester_benchmark_pair;
    use crate::geometry::{PoseCtx, kb_at, locus};
    use crate::pose::WheelsetPose;

    /// The largest turn between successive chords of the yawed locus (cosine; < 0 where the
    /// locus reverses) and its largest curvature (change of the chord angle per locus arc
    /// length), over the travelled profile at 20 µm spacing.
    fn locus_shape(pair: &super::WheelRailPair, yaw: f64) -> (f64, f64) {
        let ctx = PoseCtx::new(
            pair,
            &WheelsetPose {
                yaw,
                roll: 0.004,
                ..Default::default()
            },
        );
        let h = 20e-6;
        let n = ((pair.wheel.length() - pair.wheel_s_tip) / h) as usize;
        let pts: Vec<[f64; 2]> = (0..=n)
            .map(|i| {
                let p = locus(pair, &ctx, pair.wheel_s_tip + i as f64 * h).p;
                [p[1], p[2]]
            })
            .collect();
        let chord = |i: usize| {
            let d = [pts[i + 1][0] - pts[i][0], pts[i + 1][1] - pts[i][1]];
            let l = d[0].hypot(d[1]);
            ([d[0] / l, d[1] / l], l)
        };
        let (mut cos_min, mut kappa) = (1.0f64, 0.0f64);
        for i in 0..n - 1 {
            let ((u, la), (v, lb)) = (chord(i), chord(i + 1));
            let c = u[0] * v[0] + u[1] * v[1];
            cos_min = cos_min.min(c);
            if c > 0.0 {
                let turn = (u[0] * v[1] - u[1] * v[0]).atan2(c).abs();
                kappa = kappa.max(turn / (0.5 * (la + lb)));
            }
        }
        (cos_min, kappa)
    }

    /// The pose carries the locus factor at its yaw, and the travelling's curvature bound uses
    /// it (1 without yaw).
    #[test]
    fn the_travelling_bound_takes_the_locus_curvature_at_the_pose() {
        let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
        let pair = manchester_benchmark_pair(&root).unwrap();
        let at = |yaw: f64| {
            PoseCtx::new(
                &pair,
                &WheelsetPose {
                    yaw,
                    ..Default::default()
                },
            )
        };
        let f = pair.locus.kappa_scale(0.02f64.tan());
        assert!(f > 1.5, "{f}");
        let (yawed, straight) = (at(0.02), at(0.0));
        assert_eq!(yawed.kappa_scale, f);
        assert_eq!(straight.kappa_scale, 1.0);
        let (s_w, s_r) = (pair.wheel_s_tip + 20e-3, 30e-3);
        let [w, r] = pair.kappa_ahead(s_w, s_r);
        assert!(w > 10.0, "{w}");
        assert_eq!(kb_at(&pair, &yawed, s_w, s_r), (f * w + r).max(1.0));
        assert_eq!(kb_at(&pair, &straight, s_w, s_r), (w + r).max(1.0));
    }

    #[test]
    fn the_yawed_locus_is_regular_up_to_the_yaw_limit_and_folds_past_the_cusp() {
        let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
        let pair = manchester_benchmark_pair(&root).unwrap();
        let l = pair.locus;
        // The S1002 flange root: rho rho'' about 880 (K carries 2 % more), the cusp at
        // tan^2(yaw) K = 1, i.e. near 33.7 mrad.
        assert!(l.k > 800.0 && l.k < 1000.0, "{l:?}");
        let limit = l.tan_yaw_max.atan();
        let cusp = (1.02 / l.k).sqrt().atan();
        assert!(limit > 0.028 && limit < cusp, "limit {limit} cusp {cusp}");
        for yaw in [-limit, -0.6 * limit, 0.3 * limit, limit] {
            let (cos_min, kappa) = locus_shape(&pair, yaw);
            // regular: the chords turn by at most a few degrees over 20 µm
            assert!(
                cos_min > 0.99,
                "yaw {yaw}: the locus turns back ({cos_min})"
            );
            // its curvature within the bound the searches use
            let bound = l.kappa_scale(yaw.tan()) * pair.wheel_kappa_max;
            assert!(
                kappa <= 1.02 * bound,
                "yaw {yaw}: curvature {kappa} > bound {bound}"
            );
            // the bound is needed: beyond the profile's own curvature near the limit
            if yaw.abs() == limit {
                assert!(kappa > 2.0 * pair.wheel_kappa_max, "{kappa}");
            }
        }
        // past the cusp (2 % beyond the exact one) the locus reverses near the flange root
        let (cos_min, _) = locus_shape(&pair, 1.02 * cusp);
        assert!(cos_min < 0.0, "no fold at {} rad: {cos_min}", 1.02 * cusp);
    }
}
