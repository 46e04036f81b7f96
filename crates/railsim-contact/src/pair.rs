//! The immutable description of one wheel/rail pair: profiles, their placement, material and
//! friction. Built once from a [`PairSpec`]; shared by every evaluation.

use railsim_elastic::Material;
use railsim_profile::{ArcCurve, Profile, RailPlacement, place_rail};

use crate::broad::ArcTree;
use crate::error::ContactError;

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
    /// \[-\] Coulomb friction coefficient
    pub mu: f64,
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
    /// \[-\] Coulomb friction coefficient
    pub mu: f64,
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
    /// \[1/m\] largest |curvature| of the wheel curve plus that of the rail curve
    pub kappa_max: f64,
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
    /// \[1/m\] bound on the relative curvature of the pair over the window ahead of (s_w, s_r).
    #[inline]
    pub fn kappa_bound(&self, s_w: f64, s_r: f64) -> f64 {
        let iw = ((s_w * self.wheel_inv_ds) as usize).min(self.wheel_kappa_ahead.len() - 1);
        let ir = ((s_r * self.rail_inv_ds) as usize).min(self.rail_kappa_ahead.len() - 1);
        self.wheel_kappa_ahead[iw] + self.rail_kappa_ahead[ir]
    }
}

impl WheelRailPair {
    /// Build the pair: splines, arc-length curves and the rail placement.
    pub fn new(spec: &PairSpec) -> Result<Self, ContactError> {
        for (what, v) in [
            ("r0", spec.r0),
            ("flange_back_distance", spec.flange_back_distance),
            ("gauge", spec.gauge),
            ("gauge_depth", spec.gauge_depth),
            ("curve_ds", spec.curve_ds),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ContactError::BadOption {
                    key: what,
                    value: format!("{v}"),
                    expected: "a positive finite length in metres".into(),
                });
            }
        }
        if !(spec.mu.is_finite() && spec.mu > 0.0 && spec.mu < 2.0) {
            return Err(ContactError::BadOption {
                key: "mu",
                value: format!("{}", spec.mu),
                expected: "a friction coefficient in (0, 2)".into(),
            });
        }
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
        let kappa_max = largest(&wheel_kappa_ahead) + largest(&rail_kappa_ahead);
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
            mu: spec.mu,
            wheel_kappa_ahead,
            rail_kappa_ahead,
            wheel_inv_ds,
            rail_inv_ds,
            wheel_tree,
            rail_tree,
            kappa_max,
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
