//! Rigid 2-D wheelset/track geometry: rolling-radius difference and equivalent conicity.
//!
//! A side product of the profile geometry, computed the textbook way (contact-theory §6.1):
//! a rigid wheelset with zero yaw on rigid rails; for a lateral displacement `y_ws` the roll
//! angle and height are adjusted so that both wheels touch their rails, each contact being the
//! point of minimum vertical gap (equivalent to a common normal in 2-D).
//!
//! Frames and signs:
//! * Track frame: Y lateral, **positive to the left**, Z up. The left rail is placed with
//!   [`place_rail`] (its side frame is the track frame); the right rail is its mirror image.
//! * Wheelset: `y_ws` positive to the left, roll φ positive when the left wheel rises. The
//!   wheel profile point y (= S) of the left wheel lies at axial distance
//!   `fb/2 - y_fb + y` from the wheelset centre (fb = flange-back spacing, y_fb = flange-back
//!   position on the profile, -70 mm for S1002), radius r0 - z; the right wheel is the mirror
//!   image.
//! * **Δr = r_L - r_R**; for y_ws > 0 the left wheel runs toward its flange and Δr > 0.
//! * Contact angles are the slope angle of the wheel profile at the contact in the side frame
//!   of that wheel (positive when the surface rises toward the field side: ≈ +1.4° on the
//!   S1002 tread, ≈ +70° on the flange flank).

use crate::{ArcCurve, CurvePoint, DEFAULT_DS, Profile, ProfileError, place_rail};

/// Wheelset and track data for the rigid contact geometry.
#[derive(Clone, Copy, Debug)]
pub struct WheelsetTrackSetup {
    /// \[m\] track gauge, measured `gauge_depth` below the top of rail (1.435)
    pub gauge: f64,
    /// \[m\] depth below the top of rail at which the gauge is measured (0.014)
    pub gauge_depth: f64,
    /// \[rad\] rail inclination toward the track centre (atan(1/40)); 0 for an inclined file
    pub inclination_rad: f64,
    /// \[m\] flange-back spacing (1.360)
    pub flange_back_spacing: f64,
    /// \[m\] lateral position y of the flange back on the wheel profile (-0.070 for S1002)
    pub flange_back_y: f64,
    /// \[m\] nominal rolling radius (radius at profile z = 0), 0.460
    pub r0: f64,
}

impl Default for WheelsetTrackSetup {
    fn default() -> Self {
        WheelsetTrackSetup {
            gauge: 1.435,
            gauge_depth: 0.014,
            inclination_rad: (1.0f64 / 40.0).atan(),
            flange_back_spacing: 1.360,
            flange_back_y: -0.070,
            r0: 0.460,
        }
    }
}

/// Rigid contact state of the wheelset at one lateral displacement.
#[derive(Clone, Copy, Debug)]
pub struct DeltaRSample {
    /// \[m\] lateral wheelset displacement, positive to the left
    pub y_ws: f64,
    /// \[m\] rolling-radius difference r_L - r_R
    pub delta_r: f64,
    /// \[m\] rolling radius of the left wheel
    pub r_left: f64,
    /// \[m\] rolling radius of the right wheel
    pub r_right: f64,
    /// \[m\] contact position on the left wheel profile (profile y = S)
    pub y_contact_wheel_left: f64,
    /// \[m\] contact position on the right wheel profile (profile y = S)
    pub y_contact_wheel_right: f64,
    /// \[m\] contact position on the left rail, side frame (from the track centre)
    pub y_contact_rail_left: f64,
    /// \[m\] contact position on the right rail, side frame (from the track centre)
    pub y_contact_rail_right: f64,
    /// \[rad\] contact angle on the left wheel
    pub contact_angle_left: f64,
    /// \[rad\] contact angle on the right wheel
    pub contact_angle_right: f64,
    /// \[rad\] wheelset roll angle (positive: left wheel up)
    pub roll: f64,
    /// \[m\] height of the wheelset centre above the top of rail
    pub z_ws: f64,
}

/// Precomputed rigid wheelset/track geometry (one wheel and one rail profile, used on both
/// sides).
#[derive(Clone, Debug)]
pub struct WheelsetTrack {
    wheel: ArcCurve,
    rail: ArcCurve,
    /// \[m\] axial position of the wheel profile origin
    a0: f64,
    r0: f64,
    /// coarse scan stride in wheel nodes
    stride: usize,
}

/// Result of the minimum-gap search on one side.
#[derive(Clone, Copy, Debug)]
struct Side {
    gap: f64,
    s_wheel: f64,
    y_rail: f64,
}

impl WheelsetTrack {
    /// Builds the geometry: the wheel profile (crate wheel frame) and the rail profile (as read,
    /// placed with [`place_rail`] using the setup's gauge and inclination) become interpolating
    /// [`ArcCurve`]s at 0.05 mm.
    pub fn new(
        wheel: &Profile,
        rail: &Profile,
        setup: &WheelsetTrackSetup,
    ) -> Result<Self, ProfileError> {
        let (placed, _) = place_rail(rail, setup.inclination_rad, setup.gauge, setup.gauge_depth)?;
        let w = ArcCurve::from_profile(wheel, 0.0, DEFAULT_DS)?;
        let r = ArcCurve::from_profile(&placed, 0.0, DEFAULT_DS)?;
        let stride = ((0.25e-3 / w.ds()).round() as usize).max(1);
        Ok(WheelsetTrack {
            wheel: w,
            rail: r,
            a0: 0.5 * setup.flange_back_spacing - setup.flange_back_y,
            r0: setup.r0,
            stride,
        })
    }

    /// Vertical gap at wheel arc length `s` for lateral offset `y` and roll `phi` (wheelset
    /// centre at height 0), with the rail y; `None` where no rail lies below.
    #[inline]
    fn gap(&self, s: f64, y: f64, sn: f64, cs: f64) -> Option<(f64, f64)> {
        let w = self.wheel.eval(s);
        let yw = self.a0 + w.p[0];
        let zw = w.p[1] - self.r0;
        let yt = y + cs * yw - sn * zw;
        let zt = sn * yw + cs * zw;
        let sr = self.rail.s_at_y(yt)?;
        Some((zt - self.rail.eval(sr).p[1], yt))
    }

    /// Minimum vertical gap on the left side for offset `y`, roll `phi`.
    fn side(&self, y: f64, phi: f64) -> Option<Side> {
        let (sn, cs) = phi.sin_cos();
        let nodes = self.wheel.nodes().len();
        let ds = self.wheel.ds();
        let step = self.stride as f64 * ds;
        let samples: Vec<(f64, f64)> = (0..nodes)
            .step_by(self.stride)
            .map(|k| {
                let s = k as f64 * ds;
                (s, self.gap(s, y, sn, cs).map_or(f64::INFINITY, |g| g.0))
            })
            .collect();
        let gmin = samples.iter().map(|v| v.1).fold(f64::INFINITY, f64::min);
        if !gmin.is_finite() {
            return None;
        }
        let mut best: Option<Side> = None;
        for k in 0..samples.len() {
            let g = samples[k].1;
            let left = if k > 0 {
                samples[k - 1].1
            } else {
                f64::INFINITY
            };
            let right = samples.get(k + 1).map_or(f64::INFINITY, |v| v.1);
            if !(g <= left && g <= right && g <= gmin + 1e-4) {
                continue;
            }
            // Golden-section refinement on [s - step, s + step].
            let f = |s: f64| self.gap(s, y, sn, cs).map_or(f64::INFINITY, |g| g.0);
            let (mut a, mut b) = (samples[k].0 - step, samples[k].0 + step);
            let r = 0.5 * (5f64.sqrt() - 1.0);
            let mut c = b - r * (b - a);
            let mut d = a + r * (b - a);
            let (mut fc, mut fd) = (f(c), f(d));
            for _ in 0..60 {
                if fc <= fd {
                    b = d;
                    d = c;
                    fd = fc;
                    c = b - r * (b - a);
                    fc = f(c);
                } else {
                    a = c;
                    c = d;
                    fc = fd;
                    d = a + r * (b - a);
                    fd = f(d);
                }
                if b - a < 1e-12 {
                    break;
                }
            }
            let s = 0.5 * (a + b);
            let (s, g) = if f(s) <= g {
                (s, f(s))
            } else {
                (samples[k].0, g)
            };
            if best.is_none_or(|bs| g < bs.gap) {
                let y_rail = self.gap(s, y, sn, cs).map_or(f64::NAN, |v| v.1);
                best = Some(Side {
                    gap: g,
                    s_wheel: s,
                    y_rail,
                });
            }
        }
        best
    }

    /// Rigid contact at lateral displacement `y_ws` \[m\] (positive to the left): roll and
    /// height solved so that both wheels touch (Illinois false position on the gap difference,
    /// which increases with roll), contacts at the minimum vertical gap.
    pub fn contact(&self, y_ws: f64) -> Result<DeltaRSample, ProfileError> {
        let fail = |what: &str| ProfileError::InvalidArgument {
            source_name: "WheelsetTrack::contact".into(),
            what: what.into(),
            found: format!("y_ws = {y_ws} m"),
            expected: "a displacement with both wheels over their rails".into(),
        };
        let diff = |phi: f64| -> Option<(f64, Side, Side)> {
            let l = self.side(y_ws, phi)?;
            let r = self.side(-y_ws, -phi)?;
            Some((l.gap - r.gap, l, r))
        };
        let (mut a, mut b) = (-0.05, 0.05);
        let (mut fa, _, _) = diff(a).ok_or_else(|| fail("no contact"))?;
        let (mut fb, _, _) = diff(b).ok_or_else(|| fail("no contact"))?;
        if !(fa < 0.0 && fb > 0.0) {
            return Err(fail("roll bracket"));
        }
        let mut side = 0;
        let mut phi = 0.0;
        for _ in 0..200 {
            phi = (a * fb - b * fa) / (fb - fa);
            if !(phi > a && phi < b) {
                phi = 0.5 * (a + b);
            }
            let (f, _, _) = diff(phi).ok_or_else(|| fail("no contact"))?;
            if f == 0.0 || b - a < 1e-13 {
                break;
            }
            if f < 0.0 {
                a = phi;
                fa = f;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                b = phi;
                fb = f;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
            if (b - a).abs() < 1e-13 {
                break;
            }
        }
        let (_, l, r) = diff(phi).ok_or_else(|| fail("no contact"))?;
        let wl = self.wheel.eval(l.s_wheel);
        let wr = self.wheel.eval(r.s_wheel);
        let r_left = self.r0 - wl.p[1];
        let r_right = self.r0 - wr.p[1];
        Ok(DeltaRSample {
            y_ws,
            delta_r: r_left - r_right,
            r_left,
            r_right,
            y_contact_wheel_left: wl.p[0],
            y_contact_wheel_right: wr.p[0],
            y_contact_rail_left: l.y_rail,
            y_contact_rail_right: r.y_rail,
            contact_angle_left: wl.t[1].atan2(wl.t[0]) + phi,
            contact_angle_right: wr.t[1].atan2(wr.t[0]) - phi,
            roll: phi,
            z_ws: -l.gap,
        })
    }
}

/// Rolling-radius difference and contact data at each lateral displacement in `y_ws` \[m\]
/// (positive to the left) for `wheel` on `rail` (see [`WheelsetTrack`]).
pub fn rolling_radius_difference(
    wheel: &Profile,
    rail: &Profile,
    setup: &WheelsetTrackSetup,
    y_ws: &[f64],
) -> Result<Vec<DeltaRSample>, ProfileError> {
    let g = WheelsetTrack::new(wheel, rail, setup)?;
    y_ws.iter().map(|&y| g.contact(y)).collect()
}

/// [`rolling_radius_difference`] with the contact-point jumps located: between two neighbours of
/// `y_ws` (sorted) where a wheel's contact point moves by more than `jump` \[m\], the jump is
/// bracketed by bisection to 1 nm and both ends are added to the table. Linear interpolation
/// in the table ([`delta_r_interp`]) then has a step at the jump instead of a ramp over the
/// sampling interval, which moved it by up to half the interval and biased the equivalent
/// conicity at amplitudes just above a jump (S1002 on UIC60 1:20 at 6 mm: 0.062 on a 25 µm
/// grid against 0.054 with the jump located). Where the contact point only moves fast, the
/// added samples are merely two more points of the smooth curve.
pub fn rolling_radius_difference_with_jumps(
    wheel: &Profile,
    rail: &Profile,
    setup: &WheelsetTrackSetup,
    y_ws: &[f64],
    jump: f64,
) -> Result<Vec<DeltaRSample>, ProfileError> {
    let g = WheelsetTrack::new(wheel, rail, setup)?;
    let coarse: Vec<DeltaRSample> = y_ws
        .iter()
        .map(|&y| g.contact(y))
        .collect::<Result<_, _>>()?;
    let moved = |a: &DeltaRSample, b: &DeltaRSample| {
        (b.y_contact_wheel_left - a.y_contact_wheel_left)
            .abs()
            .max((b.y_contact_wheel_right - a.y_contact_wheel_right).abs())
    };
    let mut out = Vec::with_capacity(coarse.len() + 8);
    for (k, s) in coarse.iter().enumerate() {
        if k > 0 && moved(&coarse[k - 1], s) > jump {
            let (mut lo, mut hi) = (coarse[k - 1], *s);
            while hi.y_ws - lo.y_ws > 1e-9 {
                let m = g.contact(0.5 * (lo.y_ws + hi.y_ws))?;
                if moved(&lo, &m) >= moved(&m, &hi) {
                    hi = m;
                } else {
                    lo = m;
                }
            }
            if lo.y_ws > coarse[k - 1].y_ws {
                out.push(lo);
            }
            if hi.y_ws < s.y_ws {
                out.push(hi);
            }
        }
        out.push(*s);
    }
    Ok(out)
}

/// Linear interpolation in a Δr table (samples sorted by `y_ws`); clamps outside.
pub fn delta_r_interp(samples: &[DeltaRSample], y: f64) -> f64 {
    let n = samples.len();
    if n == 0 {
        return f64::NAN;
    }
    if y <= samples[0].y_ws {
        return samples[0].delta_r;
    }
    if y >= samples[n - 1].y_ws {
        return samples[n - 1].delta_r;
    }
    let i = samples.partition_point(|s| s.y_ws <= y).clamp(1, n - 1);
    let (a, b) = (&samples[i - 1], &samples[i]);
    a.delta_r + (b.delta_r - a.delta_r) * (y - a.y_ws) / (b.y_ws - a.y_ws)
}

/// Equivalent conicity by harmonic linearisation (first harmonic / describing function,
/// contact-theory §6.1; the linearisation idea behind UIC 519 / EN 15302):
/// λ_e(ŷ) = 1/(2ŷ) · (1/π) ∫₀^{2π} Δr(ŷ sin θ) sin θ dθ, with `delta_r` \[m\] as a function of
/// y \[m\] and the amplitude ŷ \[m\] (> 0). Midpoint rule with 4000 points. e0 and r0 do not
/// enter.
pub fn equivalent_conicity_harmonic(delta_r: impl Fn(f64) -> f64, amplitude: f64) -> f64 {
    let n = 4000;
    let h = 2.0 * std::f64::consts::PI / n as f64;
    let sum: f64 = (0..n)
        .map(|i| {
            let th = (i as f64 + 0.5) * h;
            delta_r(amplitude * th.sin()) * th.sin()
        })
        .sum();
    sum * h / (std::f64::consts::PI * 2.0 * amplitude)
}

/// Equivalent conicity by the kinematic (integration) definition (contact-theory §6.1, the
/// kind of evaluation EN 15302 bases its reference method on): integrate Klingel's kinematic
/// equation y'' = -Δr(y)/(2 e0 r0) from y = ŷ, y' = 0 (RK4 in the travelled distance), measure
/// the wavelength L of one full period, and return λ_e = 4π² e0 r0 / L² together with L \[m\].
/// `e0` \[m\] is half the contact-point spacing, `r0` \[m\] the nominal radius (λ_e itself does not
/// depend on them). `None` if no full period is found within 1 km.
pub fn equivalent_conicity_kinematic(
    delta_r: impl Fn(f64) -> f64,
    amplitude: f64,
    e0: f64,
    r0: f64,
) -> Option<(f64, f64)> {
    let k = 1.0 / (2.0 * e0 * r0);
    let acc = |y: f64| -k * delta_r(y);
    let h = 1e-3;
    let (mut y, mut v, mut x) = (amplitude, 0.0, 0.0);
    let mut crossings = 0;
    for _ in 0..1_000_000 {
        let k1 = (v, acc(y));
        let k2 = (v + 0.5 * h * k1.1, acc(y + 0.5 * h * k1.0));
        let k3 = (v + 0.5 * h * k2.1, acc(y + 0.5 * h * k2.0));
        let k4 = (v + h * k3.1, acc(y + h * k3.0));
        let yn = y + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        let vn = v + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        // Count sign changes of the slope y' (extrema): the second is the return to y = ŷ.
        if (v < 0.0 && vn >= 0.0) || (v > 0.0 && vn <= 0.0) {
            crossings += 1;
            if crossings == 2 {
                let l = x + h * v / (v - vn);
                let lam = 4.0 * std::f64::consts::PI.powi(2) * e0 * r0 / (l * l);
                return Some((lam, l));
            }
        }
        y = yn;
        v = vn;
        x += h;
    }
    None
}

/// The node of a wheel profile's flange tip: its lowest left of the taping line (y < 0);
/// `None` without nodes there.
fn flange_tip(nodes: &[CurvePoint]) -> Option<usize> {
    nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| n.p[0] < 0.0)
        .min_by(|a, b| a.1.p[1].total_cmp(&b.1.p[1]))
        .map(|(i, _)| i)
}

/// The steepest point of a wheel's flange flank: where a climbing flange bears.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlangeAngle {
    /// \[rad\] the largest slope angle of the profile between the flange tip and the taping line
    /// (y = 0), against the wheel's axle: the flange angle δ of Nadal's formula.
    pub angle: f64,
    /// \[m\] where on the profile (y = S).
    pub y: f64,
}

/// The flange angle of wheel profile `wheel` (profile frame: flange at negative y, z up, the
/// taping line at y = 0 as in EN 13715): the largest slope angle atan(dz/dy) of its
/// interpolating spline between the flange tip (the lowest point left of the taping line) and
/// the taping line, nodes every [`DEFAULT_DS`] of arc length. `None` for a profile without a
/// flange: no point left of the taping line, or no flank there as steep as
/// [`MIN_FLANGE_ANGLE`] (a cone, a tread with a chamfer), or one that overhangs (90° or more:
/// not a wheel's flank).
pub fn flange_angle(wheel: &Profile) -> Result<Option<FlangeAngle>, ProfileError> {
    let curve = ArcCurve::from_profile(wheel, 0.0, DEFAULT_DS)?;
    let nodes = curve.nodes();
    let Some(tip) = flange_tip(nodes) else {
        return Ok(None);
    };
    Ok(nodes[tip..]
        .iter()
        .take_while(|n| n.p[0] <= 0.0)
        .map(|n| FlangeAngle {
            angle: n.t[1].atan2(n.t[0]),
            y: n.p[0],
        })
        .max_by(|a, b| a.angle.total_cmp(&b.angle))
        .filter(|f| (MIN_FLANGE_ANGLE..std::f64::consts::FRAC_PI_2).contains(&f.angle)))
}

/// A wheel's flange dimensions, the flange height Sh, the flange thickness Sd and the
/// flange-face measure qR, all in \[m\]: the wheel-inspection measures of UIC 510-2 and
/// EN 15313 (their naming recalled, not verified here), with the definitions and the S1002
/// values of the shared contact-theory note §5.1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlangeDimensions {
    /// Sh: the flange tip's height above the taping line, z(0) − z(tip) (S1002: 28.0 mm).
    pub height: f64,
    /// Sd: from the flange back (the profile's y = `flange_back_y`) to the flange face where it
    /// lies 10 mm from the taping line toward the tip (S1002: 32.5 mm).
    pub thickness: f64,
    /// qR: the lateral distance between that point and the flange face 2 mm from the tip
    /// (S1002: 10.79 mm); a steep, sharp flange has a small qR.
    pub qr: f64,
    /// (y, z) of the flange tip, the lowest point left of the taping line.
    pub tip: [f64; 2],
    /// (y, z) of the flange face 10 mm from the taping line toward the tip, where Sd is measured.
    pub thickness_point: [f64; 2],
    /// (y, z) of the flange face 2 mm from the tip, qR's other end.
    pub qr_point: [f64; 2],
}

/// [`FlangeDimensions`] of wheel profile `wheel` (profile frame as in [`flange_angle`]: flange
/// at negative y, z up, the taping line at y = 0, from which the heights are taken) whose
/// flange back lies at y = `flange_back_y` \[m\] (−0.070 for EN 13715 profiles such as S1002:
/// the taping line 70 mm from the wheel's inner face; it moves only where Sd is counted from).
/// The tip is the profile's lowest point left of the taping line, refined to where the
/// interpolating spline's tangent turns level (on a flat top, the spline's lowest point). The
/// face points are where the face first reaches their levels on the way from the taping line
/// toward the tip (the outermost material there, as a gauge's finger finds it), bisected on
/// the spline to 1e-12 m of arc length. `None` for a profile without such a flange: no point
/// left of the taping line, the taping line outside the profile, the lowest point at an end of
/// the profile (cut short of its tip, or a cone), or a tip 12 mm high or less (the 10 mm and
/// 2 mm levels not distinct points of its face).
pub fn flange_dimensions(
    wheel: &Profile,
    flange_back_y: f64,
) -> Result<Option<FlangeDimensions>, ProfileError> {
    let curve = ArcCurve::from_profile(wheel, 0.0, DEFAULT_DS)?;
    let nodes = curve.nodes();
    // a tip inside the profile: its lowest point left of the taping line at one of its ends is
    // a profile cut short of its tip (or a cone), whose dimensions would be wrong
    let Some(tip) = flange_tip(nodes).filter(|&k| k > 0 && k + 1 < nodes.len()) else {
        return Ok(None);
    };
    let Some(s0) = curve.s_at_y(0.0) else {
        return Ok(None);
    };
    let z0 = curve.eval(s0).p[1];
    let ds = curve.ds();
    // the tip between the lowest node's neighbours (both inside the profile), where the
    // tangent turns level
    let (lo, hi) = ((tip - 1) as f64 * ds, (tip + 1) as f64 * ds);
    let tip_point = if curve.eval(lo).t[1] < 0.0 && curve.eval(hi).t[1] > 0.0 {
        bisect(&curve, lo, hi, |c| c.t[1] < 0.0)
    } else {
        nodes[tip].p
    };
    let z_tip = tip_point[1];
    let height = z0 - z_tip;
    if !height.is_finite() || height <= 0.012 {
        return Ok(None);
    }
    // where the face first reaches level `z` on the way from the taping line toward the tip:
    // the outermost material at that level, which a gauge's finger touches (a lip on the face
    // counts, a hollow behind it does not)
    let k0 = ((s0 / ds) as usize).min(nodes.len() - 2);
    let face_at = |z: f64| -> Option<[f64; 2]> {
        let k = (tip..=k0)
            .rev()
            .find(|&k| nodes[k].p[1] < z && nodes[k + 1].p[1] >= z)?;
        Some(bisect(&curve, k as f64 * ds, (k + 1) as f64 * ds, |c| {
            c.p[1] < z
        }))
    };
    let (Some(thickness_point), Some(qr_point)) = (face_at(z0 - 0.010), face_at(z_tip + 0.002))
    else {
        return Ok(None);
    };
    Ok(Some(FlangeDimensions {
        height,
        thickness: thickness_point[0] - flange_back_y,
        qr: thickness_point[0] - qr_point[0],
        tip: tip_point,
        thickness_point,
        qr_point,
    }))
}

/// The point of `curve` where `before` turns false between arc lengths `lo` (true) and `hi`
/// (false), bisected to 1e-12 m of arc length.
fn bisect(
    curve: &ArcCurve,
    mut lo: f64,
    mut hi: f64,
    before: impl Fn(&CurvePoint) -> bool,
) -> [f64; 2] {
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if before(&curve.eval(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve.eval(0.5 * (lo + hi)).p
}

/// \[rad\] the least slope a flank must reach to count as a flange in [`flange_angle`] (45°;
/// wheel flanges are built at 60–75°, treads at a few degrees).
pub const MIN_FLANGE_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// Nadal's limit of the quotient Y/Q of a flange climbing on its rail (Nadal 1896; e.g. Iwnicki
/// (ed.), *Handbook of Railway Vehicle Dynamics*, 2006, ch. 8): the wheel slides up the rail
/// when `Y/Q > (tan δ − μ) / (1 + μ tan δ)`, δ the flange angle \[rad\] and μ the friction
/// coefficient at the flange.
pub fn nadal_limit(flange_angle: f64, mu: f64) -> f64 {
    let t = flange_angle.tan();
    (t - mu) / (1.0 + mu * t)
}
