//! The nonlinear dissipative suspension laws: dry friction with a stick stiffness, and a
//! damper with a force–velocity table (blow-off), optionally in series with its mount
//! stiffness. Pure functions of an element's deflection, its rate and its internal state; the
//! simulator integrates the state (`docs/models/vehicle.md`).
//!
//! **Friction** (one local axis). A Coulomb slider of sliding force `F0` in series with a stick
//! stiffness `k` (the elasticity of the rubbing parts and their links): the elastoplastic
//! "Jenkins" element. Its state is the slider position `s`; the element's tension is
//! `e = k (Δ − s)` and the force on body 2 is `−e`. The slider moves only when the tension
//! reaches `F0`, in the direction that would raise it further. Written as a smooth
//! rate-independent law (Bouc 1967, Wen 1976, with the exponents β = γ = 1/2 that make the
//! yield surface exactly `|e| = F0`):
//!
//! `ṡ = Δ̇ · H(Δ̇ e) · min((|e| / F0)^n, 2)  +  (e − sat(e, F0)) / (k τ)`
//!
//! with `H` the unit step. Below yield the slider creeps by the factor `(|e|/F0)^n` (the
//! rounding of the corners of the elastoplastic loop; n = [`FRICTION_EXPONENT`]), in steady
//! sliding `ṡ = Δ̇` and `e = F0` exactly, and when stuck (`Δ̇ = 0`) it does not move at all: no
//! creep under a held load. A sliding force that falls while the element slides (the normal
//! load of a load-dependent friction drops) is followed by `(|e|/F0)^n > 1`: the slider runs
//! ahead of the deflection; the factor is bounded by 2 ([`FRICTION_RATE_CAP`]) for abrupt
//! drops. The second term acts only when `|e| > F0` and lets a held element give way when its
//! sliding force falls, with the time constant τ = [`FRICTION_RELAXATION_S`].
//!
//! The sliding force is floored at `k · 1 µm` (or `k · 1 µrad`, [`FRICTION_MIN_STICK`]): as
//! `F0 → 0` (the rubbing surfaces of a load-dependent friction part when its normal element
//! turns the other way) the transition's width `F0/n` vanishes and the law's slope
//! `n |Δ̇| / (F0/k)` grows without bound, and at `F0 = 0` the step `H(Δ̇ e)` switches the slider
//! on and off about `e = 0` (a sliding mode: an adaptive integrator stalls on it). With the
//! floor a parted element carries at most `k · 1 µm` (10 N for a stick stiffness of 10 MN/m)
//! and its slope stays below `n |Δ̇| / 1 µm`, which the implicit integrators take.
//!
//! The law is stiff near yield: its rate falls off with the tension over `F0/n`, a time scale
//! of `F0 / (n k |Δ̇|)` (1 ms for F0 = 5 kN, k = 5 MN/m, Δ̇ = 50 mm/s). The adaptive and implicit
//! integrators resolve it; a fixed step must stay below about 2.8 times it.
//!
//! **Damper** (one local axis). A force–velocity law `f_d(v)`, piecewise linear through the
//! table, strictly increasing and zero at rest. Without a series stiffness the force on body 2
//! is `−f_d(Δ̇)`. With a series (mount) stiffness `k` the damper's elongation `s` is a state:
//! the same tension passes through spring and damper, `k (Δ − s) = f_d(ṡ)`, so
//! `ṡ = f_d⁻¹(k (Δ − s))`; a linear table `f_d = c v` gives back the series spring-damper
//! exactly. The time scale `f_d'/k` is the element's stiffness for an explicit integrator.

/// \[m\] (\[rad\] for a rotational friction) the least stick deflection at yield: the sliding
/// force is at least the stick stiffness times this (module docs).
pub const FRICTION_MIN_STICK: f64 = 1e-6;

/// The exponent `n` of the friction law's transition from stick to slip. At 20 the slider has
/// moves at 5 % of the deflection rate at 0.86 F0 and at 36 % at 0.95 F0; the energy a cycle
/// of amplitude 3, 10 and 30 F0/k dissipates is 0.09 %, 0.02 % and 0.01 % below the
/// elastoplastic loop's (test `friction_loop_dissipates_the_elastoplastic_energy`).
pub const FRICTION_EXPONENT: i32 = 20;

/// The largest ratio of the slider's rate to the deflection rate, reached at
/// |e| = [`FRICTION_RATE_CAP_RATIO`] F0: the law's `(|e|/F0)^n` is not cut at 1 (a sliding
/// force that falls while the element slides is followed within 0.03 % for a fall of 1 % of the
/// deflection's stiffness, k_f Δ̇), but bounded where the sliding force drops abruptly.
pub const FRICTION_RATE_CAP: f64 = 2.0;

/// `2^(1/n)`: the tension ratio |e|/F0 at which `(|e|/F0)^n` reaches [`FRICTION_RATE_CAP`].
pub const FRICTION_RATE_CAP_RATIO: f64 = 1.035_264_923_841_377_2;

/// \[s\] time constant with which a friction slider gives way when its tension exceeds the
/// sliding force (after the sliding force fell). 1 ms keeps the law within the stability
/// region of the fixed-step RK4 at 2 ms (|h λ| = 2 < 2.78).
pub const FRICTION_RELAXATION_S: f64 = 1e-3;

/// The Bouc–Wen factor `min((|e|/F0)^n, 2)` of the slider's rate, for the tension's magnitude
/// `ae` and the sliding force `f0` (≥ 0; 2 when it is 0).
fn slip_factor(ae: f64, f0: f64) -> f64 {
    if ae >= FRICTION_RATE_CAP_RATIO * f0 {
        FRICTION_RATE_CAP
    } else {
        (ae / f0).powi(FRICTION_EXPONENT)
    }
}

/// Friction element: the force on body 2 along the axis \[N\] and the slider's rate \[m/s\], for
/// stick stiffness `k` \[N/m\] (> 0), sliding force `f0` \[N\] (at least `k` ×
/// [`FRICTION_MIN_STICK`]),
/// deflection `delta` \[m\], its rate `delta_rate` \[m/s\] and slider position `s` \[m\] (module
/// docs).
pub fn friction_law(k: f64, f0: f64, delta: f64, delta_rate: f64, s: f64) -> (f64, f64) {
    let e = k * (delta - s);
    let f0 = f0.max(k * FRICTION_MIN_STICK);
    let ae = e.abs();
    let mut rate = 0.0;
    if delta_rate * e > 0.0 {
        rate = delta_rate * slip_factor(ae, f0);
    }
    if ae > f0 {
        rate += (e - f0.copysign(e)) / (k * FRICTION_RELAXATION_S);
    }
    (-e, rate)
}

/// Planar friction element: dry friction in a plane with one sliding force for any direction
/// (a circular limit |e| ≤ F0, as for a rubbing plate or a link that slides both ways), the two
/// components along two local axes. The force on body 2 \[N\] and the slider's rates \[m/s\]
/// for stick stiffness `k` \[N/m\] (isotropic), sliding force `f0` \[N\], deflection `delta`
/// \[m\], its rate `delta_rate` \[m/s\] and slider position `s` \[m\].
///
/// The same law as [`friction_law`] with the associated flow rule of isotropic plasticity (the
/// slider moves along the tension, by the part of the deflection rate along it): with
/// `e = k (Δ − s)`,
///
/// `ṡ = H(e·Δ̇) · min((|e|/F0)^n, 2) · (e·Δ̇) e / |e|²  +  (e − F0 e/|e|)⁺ / (k τ)`,
///
/// the biaxial Bouc–Wen form (Park, Wen & Ang, *Earthquake Eng. Struct. Dyn.* 14, 1986) with
/// β = γ = 1/2. Along one axis it is [`friction_law`] exactly. Two one-axis elements at right
/// angles would let the resultant reach √2 F0 when sliding diagonally; this one holds F0.
pub fn planar_friction_law(
    k: f64,
    f0: f64,
    delta: [f64; 2],
    delta_rate: [f64; 2],
    s: [f64; 2],
) -> ([f64; 2], [f64; 2]) {
    let e = [k * (delta[0] - s[0]), k * (delta[1] - s[1])];
    let f0 = f0.max(k * FRICTION_MIN_STICK);
    let ae = e[0].hypot(e[1]);
    let mut rate = [0.0; 2];
    let power = e[0] * delta_rate[0] + e[1] * delta_rate[1];
    if power > 0.0 {
        let lambda = slip_factor(ae, f0) * power / (ae * ae);
        rate = [lambda * e[0], lambda * e[1]];
    }
    if ae > f0 {
        let excess = (ae - f0) / (ae * k * FRICTION_RELAXATION_S);
        rate = [rate[0] + excess * e[0], rate[1] + excess * e[1]];
    }
    ([-e[0], -e[1]], rate)
}

/// A damper's force–velocity law: piecewise linear through the points, extrapolated with the
/// end slopes; strictly increasing and zero at zero velocity (checked when the vehicle is
/// compiled), so that it can be inverted.
#[derive(Debug, Clone, PartialEq)]
pub struct DamperTable {
    /// \[m/s\] velocities, strictly increasing.
    pub velocity: Vec<f64>,
    /// \[N\] damper force (tension positive) at each velocity, strictly increasing.
    pub force: Vec<f64>,
    /// The table is given for v ≥ 0 and mirrored: f(−v) = −f(v).
    pub symmetric: bool,
}

/// Linear interpolation of `y(x)` at `t` (`x` strictly increasing), extrapolated with the end
/// intervals' slopes; shared with [`crate::model::ForceTable`].
pub(crate) fn interpolate(x: &[f64], y: &[f64], t: f64) -> f64 {
    let n = x.len();
    let i = match x.partition_point(|&xi| xi <= t) {
        0 => 0,
        k if k >= n => n - 2,
        k => k - 1,
    };
    y[i] + (y[i + 1] - y[i]) * (t - x[i]) / (x[i + 1] - x[i])
}

impl DamperTable {
    /// \[N\] damper force (tension) at elongation rate `v` \[m/s\].
    pub fn force(&self, v: f64) -> f64 {
        if self.symmetric && v < 0.0 {
            return -self.force(-v);
        }
        interpolate(&self.velocity, &self.force, v)
    }

    /// \[m/s\] the elongation rate at which the damper carries the tension `f` \[N\]: the inverse
    /// of [`force`](Self::force).
    pub fn velocity(&self, f: f64) -> f64 {
        if self.symmetric && f < 0.0 {
            return -self.velocity(-f);
        }
        interpolate(&self.force, &self.velocity, f)
    }
}

/// Damper with a series stiffness `k` \[N/m\]: the force on body 2 \[N\] and the damper's
/// elongation rate \[m/s\] at deflection `delta` \[m\] and damper elongation `s` \[m\].
pub fn damper_series_law(table: &DamperTable, k: f64, delta: f64, s: f64) -> (f64, f64) {
    let e = k * (delta - s);
    (-e, table.velocity(e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Energy dissipated by the friction element over its third cycle of a prescribed
    /// deflection Δ = A sin(2π t) (classical RK4 on the slider, 20 000 steps a cycle, the work
    /// ∮ e dΔ by the trapezoidal rule).
    fn loop_energy(k: f64, f0: f64, a: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI;
        let n = 20_000;
        let h = 1.0 / n as f64;
        let rate = |t: f64, s: f64| {
            let (d, dd) = (a * (w * t).sin(), a * w * (w * t).cos());
            friction_law(k, f0, d, dd, s).1
        };
        let (mut s, mut work) = (0.0, 0.0);
        for step in 0..3 * n {
            let t = step as f64 * h;
            let k1 = rate(t, s);
            let k2 = rate(t + 0.5 * h, s + 0.5 * h * k1);
            let k3 = rate(t + 0.5 * h, s + 0.5 * h * k2);
            let k4 = rate(t + h, s + h * k3);
            let d0 = a * (w * t).sin();
            let e0 = k * (d0 - s);
            s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            let d1 = a * (w * (t + h)).sin();
            let e1 = k * (d1 - s);
            if step >= 2 * n {
                work += 0.5 * (e0 + e1) * (d1 - d0);
            }
        }
        work
    }

    #[test]
    fn friction_loop_dissipates_the_elastoplastic_energy() {
        let (k, f0) = (5e6, 1e4);
        let yield_d = f0 / k;
        for m in [3.0, 10.0, 30.0] {
            let a = m * yield_d;
            let exact = 4.0 * f0 * (a - yield_d);
            let got = loop_energy(k, f0, a);
            let rel = got / exact - 1.0;
            eprintln!(
                "amplitude {m} F0/k: loop energy {got:.4} J, elastoplastic {exact:.4} J, {rel:+.4}"
            );
            assert!(rel.abs() < 0.002, "{rel}");
        }
        // Below yield the loop closes: no slip but the creep of the smooth transition.
        let a = 0.5 * yield_d;
        let got = loop_energy(k, f0, a);
        assert!(got.abs() < 1e-5 * 4.0 * f0 * a, "{got}");
    }

    #[test]
    fn friction_sticks_when_held_and_slides_at_its_force() {
        let (k, f0) = (5e6, 1e4);
        // Held below the sliding force: no creep at all.
        assert_eq!(friction_law(k, f0, 1.5e-3, 0.0, 0.0).1, 0.0);
        // Unloading (rate against the tension): elastic, the slider stays.
        assert_eq!(friction_law(k, f0, 1.5e-3, -0.1, 0.0).1, 0.0);
        // At the sliding force, moving on: the slider follows exactly (steady sliding).
        let (f, r) = friction_law(k, f0, f0 / k + 0.01, 0.2, 0.01);
        assert!((f + f0).abs() < 1e-9 && (r - 0.2).abs() < 1e-12, "{f} {r}");
        // Rate independent: the slip rate scales with the deflection rate.
        let (_, r1) = friction_law(k, f0, 1.9e-3, 0.01, 0.0);
        let (_, r2) = friction_law(k, f0, 1.9e-3, 0.03, 0.0);
        assert!((r2 - 3.0 * r1).abs() < 1e-15, "{r1} {r2}");
        // Above the sliding force (it fell): the slider gives way with the relaxation time,
        // also when held.
        let (f, r) = friction_law(k, 0.5 * f0, f0 / k, 0.0, 0.0);
        assert!((f + f0).abs() < 1e-6);
        assert!(
            (r - 0.5 * f0 / (k * FRICTION_RELAXATION_S)).abs() < 1e-12,
            "{r}"
        );
        // A sliding force that falls while the element slides: the slider runs ahead of
        // the deflection, at most twice as fast.
        let (_, r) = friction_law(k, 0.99 * f0, f0 / k, 0.2, 0.0);
        assert!(r > 0.2 && r < 0.4, "{r}");
        let (_, r) = friction_law(k, 0.5 * f0, f0 / k, 0.2, 0.0);
        let relax = 0.5 * f0 / (k * FRICTION_RELAXATION_S);
        assert!((r - (0.4 + relax)).abs() < 1e-12, "{r}");
        assert!(
            (FRICTION_RATE_CAP_RATIO.powi(FRICTION_EXPONENT) - FRICTION_RATE_CAP).abs() < 1e-12
        );
        // No sliding force (a load-dependent friction whose surfaces parted): the element
        // gives way to any tension beyond its floor k · 1 µm, and slides at the floor.
        let floor = k * FRICTION_MIN_STICK;
        let (_, r) = friction_law(k, 0.0, 2e-6, 0.0, 0.0);
        assert!(r > 0.0);
        assert_eq!(friction_law(k, 0.0, 0.5e-6, 0.0, 0.0).1, 0.0);
        // (1e-6 + 0.01 - 0.01 keeps 1e-6 to 7e-13 relative: the slip factor's 20th power to
        // 1.5e-11)
        let (f, r) = friction_law(k, 0.0, 1e-6 + 0.01, 0.2, 0.01);
        assert!(
            (f + floor).abs() < 1e-9 && (r - 0.2).abs() < 1e-10,
            "{f} {r}"
        );
        assert_eq!(
            friction_law(k, 0.0, 3e-6, 0.3, 1e-6),
            friction_law(k, floor, 3e-6, 0.3, 1e-6)
        );
        // Odd in the deflection.
        let (fa, ra) = friction_law(k, f0, 1.9e-3, 0.05, 1e-4);
        let (fb, rb) = friction_law(k, f0, -1.9e-3, -0.05, -1e-4);
        assert_eq!((fa, ra), (-fb, -rb));
    }

    #[test]
    fn planar_friction_along_one_axis_is_the_friction_law() {
        let (k, f0) = (5e6, 1e4);
        for (d, r, s) in [
            (1.9e-3, 0.05, 1e-4),
            (-2.5e-3, -0.2, -0.4e-3),
            (1.5e-3, -0.1, 0.0),
            (3e-3, 0.0, 0.0),
        ] {
            let (f1, r1) = friction_law(k, f0, d, r, s);
            for (c, sn) in [(1.0, 0.0), (0.0, 1.0), (0.6, -0.8)] {
                let (f2, r2) =
                    planar_friction_law(k, f0, [c * d, sn * d], [c * r, sn * r], [c * s, sn * s]);
                let scale = 1.0 + f1.abs();
                assert!(
                    (f2[0] - c * f1).abs() < 1e-9 * scale && (f2[1] - sn * f1).abs() < 1e-9 * scale
                );
                assert!(
                    (r2[0] - c * r1).abs() < 1e-12 && (r2[1] - sn * r1).abs() < 1e-12,
                    "{r1} {r2:?}"
                );
            }
        }
    }

    /// Driven round a circle of radius A ≫ F0/k, the slider settles on a circle of radius
    /// ρ = √(A² − (F0/k)²) with the tension F0 along its path: the element dissipates 2π ρ F0
    /// per turn and its force never exceeds F0 (two one-axis elements would reach √2 F0).
    #[test]
    fn planar_friction_round_a_circle_holds_its_circular_limit() {
        let (k, f0, a) = (5e6, 1e4, 20e-3);
        let w = 2.0 * std::f64::consts::PI;
        let n = 40_000;
        let h = 1.0 / n as f64;
        let drive = |t: f64| {
            let (c, sn) = ((w * t).cos(), (w * t).sin());
            ([a * c, a * sn], [-a * w * sn, a * w * c])
        };
        let rate = |t: f64, s: [f64; 2]| {
            let (d, dd) = drive(t);
            planar_friction_law(k, f0, d, dd, s).1
        };
        let add = |s: [f64; 2], r: [f64; 2], c: f64| [s[0] + c * r[0], s[1] + c * r[1]];
        let (mut s, mut work, mut peak) = ([0.0, 0.0], 0.0, 0.0f64);
        for step in 0..3 * n {
            let t = step as f64 * h;
            let k1 = rate(t, s);
            let k2 = rate(t + 0.5 * h, add(s, k1, 0.5 * h));
            let k3 = rate(t + 0.5 * h, add(s, k2, 0.5 * h));
            let k4 = rate(t + h, add(s, k3, h));
            let s1 = [
                s[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
                s[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
            ];
            if step >= 2 * n {
                // the slider's work: tension times the slider's step (midpoint tension)
                let (d0, _) = drive(t);
                let (d1, _) = drive(t + h);
                let e0 = [k * (d0[0] - s[0]), k * (d0[1] - s[1])];
                let e1 = [k * (d1[0] - s1[0]), k * (d1[1] - s1[1])];
                let em = [0.5 * (e0[0] + e1[0]), 0.5 * (e0[1] + e1[1])];
                work += em[0] * (s1[0] - s[0]) + em[1] * (s1[1] - s[1]);
                peak = peak.max(e1[0].hypot(e1[1]));
            }
            s = s1;
        }
        let rho = (a * a - (f0 / k).powi(2)).sqrt();
        let exact = w * rho * f0;
        eprintln!("per turn {work:.4} J against 2 pi rho F0 = {exact:.4} J; peak {peak:.2} N");
        assert!((work / exact - 1.0).abs() < 1e-3, "{work} {exact}");
        assert!(peak <= 1.0005 * f0 && peak > 0.999 * f0, "{peak}");
    }

    #[test]
    fn a_damper_table_inverts_and_a_linear_one_is_the_series_spring_damper() {
        let t = DamperTable {
            velocity: vec![0.0, 0.1, 0.5],
            force: vec![0.0, 10e3, 14e3],
            symmetric: true,
        };
        for v in [-0.9, -0.3, -0.05, 0.0, 0.02, 0.1, 0.3, 0.7] {
            let f = t.force(v);
            assert!((t.velocity(f) - v).abs() < 1e-12, "{v}");
        }
        // blow-off: 100 kN·s/m below 0.1 m/s, 10 kN·s/m above
        assert!((t.force(0.05) - 5e3).abs() < 1e-9);
        assert!((t.force(0.3) - 12e3).abs() < 1e-9);
        assert!((t.force(-0.3) + 12e3).abs() < 1e-9);
        assert!((t.force(1.0) - 19e3).abs() < 1e-9, "end slope extrapolated");
        let c = 250e3;
        let lin = DamperTable {
            velocity: vec![-1.0, 1.0],
            force: vec![-c, c],
            symmetric: false,
        };
        let k = 6e6;
        for (d, s) in [(1e-3, 2e-4), (-4e-3, 1e-3), (0.0, 0.0)] {
            let (f, r) = damper_series_law(&lin, k, d, s);
            assert!((f - crate::model::series_force(k, d, s)).abs() < 1e-9);
            let want = crate::model::series_state_rate(k, c, d, s);
            assert!((r - want).abs() < 1e-12 * (1.0 + want.abs()), "{r} {want}");
        }
    }
}
