//! `VehicleModel`: the compiled, immutable vehicle (SI, names resolved to typed ids, checked).

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use railsim_spec::short_number;
use toml::Spanned;

use crate::error::{Sink, VehicleError, did_you_mean};
use crate::linalg::{Mat3, cholesky, rotation_rpy, sym3_eigenvalues};
use crate::spec::{
    BodySpec, ForceSpec, NumberOrTriple, OutOfRoundnessSpec, VehicleSpec, WheelsetSpec,
};
use crate::suspension::DamperTable;

/// \[m/s²\] gravitational acceleration used when the file gives none.
pub const DEFAULT_GRAVITY: f64 = 9.81;
/// \[m\] farthest an attachment point may lie from the centre of gravity of a body it attaches.
pub const MAX_REACH_BODY: f64 = 15.0;
/// \[m\] farthest an attachment point may lie from the axle centre of a wheelset it attaches.
pub const MAX_REACH_WHEELSET: f64 = 2.0;
/// \[m\] largest |y| of an attachment point or centre of gravity (half a loading gauge).
pub const MAX_HALF_WIDTH: f64 = 2.5;
/// \[m\] range of z of an attachment point or centre of gravity (track level to roof).
pub const Z_RANGE: (f64, f64) = (-0.5, 6.0);
/// \[kg\] plausible mass of one body or wheelset (a loaded 4-axle wagon is about 90 t).
pub const MASS_RANGE: (f64, f64) = (1.0, 1e6);
/// \[kg·m²\] largest plausible principal moment of inertia (a 26 m coach body: about 2e6).
pub const MAX_INERTIA: f64 = 1e8;
/// \[kg·m²\] smallest plausible principal moment of inertia (the lightest body accepted, 1 kg,
/// at a radius of gyration of 3 cm); a smaller one is a unit error and makes the rotation so
/// fast that a run cannot advance.
pub const MIN_INERTIA: f64 = 1e-3;
/// \[N·m\] largest plausible traction or brake torque on one axle (a heavy-haul locomotive's
/// is some tens of kN·m).
pub const MAX_AXLE_TORQUE: f64 = 1e6;
/// \[N/m\] largest plausible translational stiffness of a force element (each axis of a
/// bushing, a series, stick or mount stiffness) and largest slope of a force table. The
/// stiffest shipped elements are about 4e7 N/m (a primary spring's kx, 3.1e7; the last segment
/// of the Manchester bump stop, 4.0e7), and a wheel–rail contact, the stiffest link of a
/// vehicle, is about 1e9. A larger value is a typing or unit error; left in, it swamps the
/// other elements in the static solve (1e20 N/m primary springs were reported as a body
/// without support) and shortens the stable step of an explicit integrator.
pub const MAX_STIFFNESS: f64 = 1e10;
/// \[N·m/rad\] largest plausible rotational stiffness: [`MAX_STIFFNESS`] at a lever of 1 m
/// (an anti-roll bar is about 1e6 N·m/rad, a side bearer's stick stiffness about 1e7).
pub const MAX_ROTATIONAL_STIFFNESS: f64 = 1e10;
/// \[N·s/m\] largest plausible viscous damping and largest slope of a damper's force–velocity
/// table. Railway dampers have 1e3 to 1e6 N·s/m (the shipped yaw damper 2.5e5); beyond 1e9 a
/// value is a typing or unit error, and its time constant m/c on a body of a tonne is below
/// 1 µs.
pub const MAX_DAMPING: f64 = 1e9;
/// \[N·m·s/rad\] largest plausible rotational damping: [`MAX_DAMPING`] at a lever of 1 m.
pub const MAX_ROTATIONAL_DAMPING: f64 = 1e9;
/// \[s\] shortest relaxation time τ = c/k of a damper in series with a spring (a
/// `series_spring_damper`, or a `damper` with a mount stiffness, τ from its table's smallest
/// slope). The damper's elongation relaxes with e^(−t/τ); an explicit integrator is stable for
/// steps up to about 2τ (2.8τ for RK4), so a τ of 1e-24 s stalls a run at t = 0 and one below
/// the smallest normal number gives NaN. Real suspension dampers on their rubber mounts have τ
/// of 1 to 100 ms (the shipped yaw damper: 250e3 / 6e6 = 42 ms; a blow-off branch 2.8 ms), so
/// 10 µs is two orders below any of them and still leaves a step of 20 µs. A stiffer mount adds
/// nothing: the damper alone is the better model.
pub const MIN_SERIES_RELAXATION: f64 = 1e-5;
/// \[N\] largest plausible |force| in a force or damper table (a buffer's end force is about
/// 1e6 N; the Manchester bump stop ends at 2.3e5 N).
pub const MAX_TABLE_FORCE: f64 = 1e8;
/// \[m\] largest plausible |deflection| in a force table (suspension strokes are about 0.1 m).
pub const MAX_TABLE_DEFLECTION: f64 = 1.0;
/// \[m/s\] largest plausible |velocity| in a damper table (damper velocities are about 1 m/s).
pub const MAX_TABLE_VELOCITY: f64 = 100.0;
/// Built-in wheel profile names (besides `"cone:λ"`).
pub const BUILTIN_WHEEL_PROFILES: [&str; 1] = ["s1002"];
/// The reserved name of the track-following frame, usable as a force element's end.
pub const TRACK: &str = "track";

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(usize);
        impl $name {
            /// The index into the model's list.
            pub fn index(self) -> usize {
                self.0
            }
        }
    };
}
id_type!(
    /// Index of a rigid body (not a wheelset) in [`VehicleModel::bodies`].
    BodyId
);
id_type!(
    /// Index of a wheelset in [`VehicleModel::wheelsets`].
    WheelsetId
);
id_type!(
    /// Index of a force element in [`VehicleModel::forces`].
    ForceElementId
);

/// A body that has degrees of freedom: a rigid body or a wheelset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Member {
    /// A rigid body.
    Body(BodyId),
    /// A wheelset.
    Wheelset(WheelsetId),
}

/// \[m\] how far along x from the carbody's centre a rigid body must be to be a bogie frame
/// ([`VehicleModel::bogies`]).
pub const BOGIE_FRAME_MIN_OFFSET: f64 = 0.5;

/// A bogie of [`VehicleModel::bogies`]: its frame and the wheelsets nearest to it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bogie {
    /// The frame.
    pub frame: BodyId,
    /// Its wheelsets, in wheelset order.
    pub wheelsets: Vec<WheelsetId>,
}

/// One end of a force element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Endpoint {
    /// The frame that follows the track at the vehicle's speed.
    Track,
    /// A rigid body or wheelset.
    Member(Member),
}

/// A degree of freedom of a body, in the vehicle frame: translations along and rotations about
/// x, y, z. For a wheelset the rotation about y is the spin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DofKind {
    /// Longitudinal translation.
    X,
    /// Lateral translation.
    Y,
    /// Vertical translation.
    Z,
    /// Rotation about x.
    Roll,
    /// Rotation about y (a wheelset's spin).
    Pitch,
    /// Rotation about z.
    Yaw,
}

impl DofKind {
    /// All six, in state order.
    pub const ALL: [DofKind; 6] = [
        DofKind::X,
        DofKind::Y,
        DofKind::Z,
        DofKind::Roll,
        DofKind::Pitch,
        DofKind::Yaw,
    ];
    /// Index 0..6 in [`DofKind::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
    /// Name as written in `frozen` for a rigid body.
    pub fn body_name(self) -> &'static str {
        ["x", "y", "z", "roll", "pitch", "yaw"][self.index()]
    }
    /// Name as written in `frozen` for a wheelset (`spin` for the rotation about y).
    pub fn wheelset_name(self) -> &'static str {
        ["x", "y", "z", "roll", "spin", "yaw"][self.index()]
    }
}

/// One degree of freedom that the simulation integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Dof {
    /// Whose.
    pub member: Member,
    /// Which.
    pub kind: DofKind,
}

/// A rigid body.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// \[kg\] mass.
    pub mass: f64,
    /// \[kg·m²\] inertia tensor about the centre of gravity, vehicle axes (symmetric, positive
    /// definite).
    pub inertia: Mat3,
    /// \[m\] centre of gravity in the vehicle frame, nominal configuration.
    pub position: [f64; 3],
    /// Frozen degrees of freedom, indexed by [`DofKind::index`].
    pub frozen: [bool; 6],
}

/// A wheel profile reference, resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum WheelProfile {
    /// The built-in S1002 profile of `railsim-profile`.
    S1002,
    /// A pure cone through the running circle (`"cone:0.15"` in the file), for analytic
    /// checks (Klingel, Wickens).
    Cone {
        /// \[-\] conicity λ (slope of the tread against the axle), in (0, 1\].
        conicity: f64,
    },
    /// A profile file (path resolved relative to the vehicle file; it exists).
    File(PathBuf),
}

/// A wheelset: a rigid body with a spin degree of freedom and two wheels.
#[derive(Debug, Clone, PartialEq)]
pub struct Wheelset {
    /// Unique name.
    pub name: String,
    /// \[kg\] mass.
    pub mass: f64,
    /// \[kg·m²\] inertia tensor about the centre of gravity (Iyy is the spin inertia).
    pub inertia: Mat3,
    /// \[m\] axle centre in the vehicle frame, nominal configuration (z = nominal radius).
    pub position: [f64; 3],
    /// \[m\] nominal rolling radius r0.
    pub nominal_radius: f64,
    /// \[m\] flange-back (back-to-back) distance.
    pub back_to_back: f64,
    /// \[m\] distance from a wheel's back face to its running circle.
    pub running_circle_from_back: f64,
    /// Wheel profiles `[left, right]`.
    pub profiles: [WheelProfile; 2],
    /// \[N·m\] constant traction (> 0) or brake (< 0) torque about the axle.
    pub torque: f64,
    /// The body that carries the torque's reaction (the motor's or brake's mount, e.g. a bogie
    /// frame); `None`: the reaction acts on nothing modelled.
    pub torque_reaction: Option<BodyId>,
    /// Frozen degrees of freedom, indexed by [`DofKind::index`] (`Pitch` is the spin).
    pub frozen: [bool; 6],
    /// The wheels' out-of-roundness `[left, right]` (empty: round wheels).
    pub out_of_roundness: [Vec<WheelDefect>; 2],
}

/// An out-of-roundness of a wheel: a deviation of its radius with the rolled angle θ (the
/// wheelset's track position over its nominal radius at the start; from there it turns with the
/// wheel's spin, the simulator's `MemberModel::rolled_angle`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WheelDefect {
    /// A polygonal wheel: `δr = amplitude cos(order θ + phase)`.
    Harmonic {
        /// waves round the wheel
        order: u32,
        /// \[m\]
        amplitude: f64,
        /// \[rad\]
        phase: f64,
    },
    /// A rounded wheel flat: `δr = −(depth/2) (1 + cos(2π d/length))` where the arc distance
    /// `d = r0 (θ − position)` (wrapped to ±π r0) is within ±length/2 of the flat's centre,
    /// zero elsewhere (the rounded, or haversine, flat of the wheel-flat impact literature,
    /// e.g. Wu & Thompson, J. Sound Vib. 251, 2002).
    Flat {
        /// \[m\] along the circumference
        length: f64,
        /// \[m\]
        depth: f64,
        /// \[rad\] rolled angle at which its centre is at the bottom
        position: f64,
    },
}

/// The radius deviation `δr` \[m\] (positive: a larger radius) of a wheel with nominal radius
/// `r0` and defects `defects` at rolled angle `theta` \[rad\], and its rate `dδr/dθ` \[m/rad\].
pub fn radius_deviation(defects: &[WheelDefect], theta: f64, r0: f64) -> (f64, f64) {
    let d = deviation_derivatives(defects, theta, r0);
    (d[0], d[1])
}

/// `[δr, dδr/dθ, d²δr/dθ²]` at rolled angle `theta` (the last jumps at a flat's ends).
fn deviation_derivatives(defects: &[WheelDefect], theta: f64, r0: f64) -> [f64; 3] {
    let mut out = [0.0; 3];
    for d in defects {
        match *d {
            WheelDefect::Harmonic {
                order,
                amplitude,
                phase,
            } => {
                let n = f64::from(order);
                let (s, c) = (n * theta + phase).sin_cos();
                out[0] += amplitude * c;
                out[1] -= amplitude * n * s;
                out[2] -= amplitude * n * n * c;
            }
            WheelDefect::Flat {
                length,
                depth,
                position,
            } => {
                let tau = std::f64::consts::TAU;
                let a = (theta - position).rem_euclid(tau);
                let arc = r0 * if a > 0.5 * tau { a - tau } else { a };
                if arc.abs() < 0.5 * length {
                    let k = tau * r0 / length;
                    let (s, c) = (tau * arc / length).sin_cos();
                    out[0] -= 0.5 * depth * (1.0 + c);
                    out[1] += 0.5 * depth * s * k;
                    out[2] += 0.5 * depth * c * k * k;
                }
            }
        }
    }
    out
}

/// Bounds of a wheel's defects over the whole rim: `[δr_min, δr_max, max |dδr/dθ|,
/// max |d²δr/dθ²|]` (sums of the defects' own bounds).
fn deviation_bounds(defects: &[WheelDefect], r0: f64) -> [f64; 4] {
    let mut b = [0.0; 4];
    for d in defects {
        match *d {
            WheelDefect::Harmonic {
                order, amplitude, ..
            } => {
                let (n, a) = (f64::from(order), amplitude.abs());
                b[0] -= a;
                b[1] += a;
                b[2] += a * n;
                b[3] += a * n * n;
            }
            WheelDefect::Flat { length, depth, .. } => {
                let k = std::f64::consts::TAU * r0 / length;
                b[0] -= depth;
                b[2] += 0.5 * depth * k;
                b[3] += 0.5 * depth * k * k;
            }
        }
    }
    b
}

/// \[m\] the B&B's resolution of the rim's support: intervals whose value cannot exceed the best
/// found by more than this are not split further.
const SUPPORT_TOL: f64 = 1e-13;

/// The out-of-round wheel's support on a flat rail: the height `e` \[m\] of the wheel centre
/// above the rail, less r0, at rolled angle `theta` \[rad\] (the material angle at the bottom),
/// and its rate `de/dθ` \[m/rad\].
///
/// The rim point at material angle θ + u lies `(r0 + δr(θ + u)) cos u` below the axle, and the
/// wheel rests on the lowest one: `e(θ) = max_u (r0 + δr(θ + u)) cos u − r0`, the rim's support
/// function in the vertical direction. By the envelope theorem `de/dθ = (r0 + δr(θ + u*)) sin u*`
/// at the maximiser u*, whose arc `r0 u*` is how far the contact lies from the bottom of the
/// wheel. For a smooth defect, e = δr + δr'²/(2 (R − δr'')) + … (R = r0 + δr, derivatives in θ):
/// on the flank of a 50 mm long, 0.2 mm deep rounded flat the contact lies up to 5.6 mm from the
/// bottom and the wheel centre up to 0.035 mm higher than δr says, and at the flat's centre the
/// centre's path is curved R/(R − δr'') = 3.7 times as much as the radius (the support function's
/// h + h″ = ρ, the rim's radius of curvature). Where the rim is concave (a deep flat) the wheel
/// bridges the hollow on two rim points and `e` has a kink where the support passes from one to
/// the other.
///
/// The maximum is found on `|u| ≤ U`, beyond which no rim point can reach below the lowest
/// possible one (`cos U = (r0 + δr_min)/(r0 + δr_max)`): where the defects' bounds make
/// `(r0 + δr) cos u` concave there, by Newton's method on its derivative, safeguarded by
/// bisection; otherwise by branch and bound with the bound `|g″| ≤ max|δr″| + 2 max|δr′| sin U +
/// r0 + δr_max` on 32 intervals split until no interval can hold a value more than 1e-13 m above
/// the best, then Newton from the best point. No allocation.
pub fn rim_support(defects: &[WheelDefect], theta: f64, r0: f64) -> (f64, f64) {
    if defects.is_empty() {
        return (0.0, 0.0);
    }
    let [lo, hi, d1, d2] = deviation_bounds(defects, r0);
    let cos_u = ((r0 + lo) / (r0 + hi)).clamp(-1.0, 1.0);
    let big_u = cos_u.acos().min(0.5);
    if big_u <= 0.0 {
        return radius_deviation(defects, theta, r0);
    }
    // g(u) = (r0 + δr(θ + u)) cos u with its first two derivatives
    let g = |u: f64| -> [f64; 3] {
        let [d, dd, ddd] = deviation_derivatives(defects, theta + u, r0);
        let (s, c) = u.sin_cos();
        let rad = r0 + d;
        [rad * c, dd * c - rad * s, ddd * c - 2.0 * dd * s - rad * c]
    };
    // Newton on g' = 0 from u0, kept in [a, b] by bisection on the sign of g' (g' decreasing
    // where g is concave).
    let newton = |u0: f64, mut a: f64, mut b: f64| -> f64 {
        let mut u = u0;
        for _ in 0..60 {
            let [_, g1, g2] = g(u);
            if g1 > 0.0 {
                a = u;
            } else {
                b = u;
            }
            let mut next = if g2 < 0.0 { u - g1 / g2 } else { f64::NAN };
            if !(next > a && next < b) {
                next = 0.5 * (a + b);
            }
            if (next - u).abs() <= 1e-15 || b - a <= 1e-15 {
                return next;
            }
            u = next;
        }
        u
    };
    let concave = d2 + 2.0 * d1 * big_u.sin() < (r0 + lo) * big_u.cos();
    let u_best = if concave {
        newton(0.0, -big_u, big_u)
    } else {
        let k = d2 + 2.0 * d1 * big_u.sin() + r0 + hi;
        const N0: usize = 32;
        // (a, b, g(a), g(b)); depth-first, so the stack grows by at most one per level
        let mut stack = [(0.0f64, 0.0f64, 0.0f64, 0.0f64); 128];
        let mut top = 0;
        let h0 = 2.0 * big_u / N0 as f64;
        let (mut best, mut best_u) = (f64::NEG_INFINITY, 0.0);
        let mut prev = (-big_u, g(-big_u)[0]);
        for i in 1..=N0 {
            let u = -big_u + h0 * i as f64;
            let gu = g(u)[0];
            for (x, gx) in [prev, (u, gu)] {
                if gx > best {
                    (best, best_u) = (gx, x);
                }
            }
            stack[top] = (prev.0, u, prev.1, gu);
            top += 1;
            prev = (u, gu);
        }
        let mut width_best = h0;
        while top > 0 {
            top -= 1;
            let (a, b, ga, gb) = stack[top];
            let slack = k * (b - a) * (b - a) / 8.0;
            if ga.max(gb) + slack <= best + SUPPORT_TOL {
                continue;
            }
            let m = 0.5 * (a + b);
            let gm = g(m)[0];
            if gm > best {
                (best, best_u, width_best) = (gm, m, 0.5 * (b - a));
            }
            if slack <= SUPPORT_TOL || top + 2 > stack.len() {
                continue;
            }
            stack[top] = (a, m, ga, gm);
            stack[top + 1] = (m, b, gm, gb);
            top += 2;
        }
        let polished = newton(
            best_u,
            (best_u - width_best).max(-big_u),
            (best_u + width_best).min(big_u),
        );
        if g(polished)[0] >= best {
            polished
        } else {
            best_u
        }
    };
    let [d, _, _] = deviation_derivatives(defects, theta + u_best, r0);
    let (s, c) = u_best.sin_cos();
    ((r0 + d) * c - r0, (r0 + d) * s)
}

impl Wheelset {
    /// \[m\] half the distance between the running circles, b (e0):
    /// back-to-back / 2 + running circle from back.
    pub fn contact_half_distance(&self) -> f64 {
        0.5 * self.back_to_back + self.running_circle_from_back
    }
}

/// A local axis of a force element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Local x.
    X,
    /// Local y.
    Y,
    /// Local z.
    Z,
}

/// How a friction element's normal load N follows from the force of its normal element: the
/// force that element exerts on its second end (`body2`), in its own local axes, preload
/// included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalLoad {
    /// The element whose force presses the rubbing surfaces together (never a friction element).
    pub element: ForceElementId,
    /// How its force gives N.
    pub rule: NormalRule,
}

/// The rule of a [`NormalLoad`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalRule {
    /// N = max(0, sign·F_axis): the component of the force on `body2` along the signed local
    /// axis, where it presses; when it turns the other way the surfaces part and N = 0.
    Along {
        /// The local axis.
        axis: Axis,
        /// Along it or against it.
        sign: Sign,
    },
    /// N = |F|, the magnitude of the whole force, whatever its direction.
    Magnitude,
}

/// The sign of a signed local axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// Along the axis (`"z"`, `"+z"`).
    Plus,
    /// Against it (`"-z"`).
    Minus,
}

impl Sign {
    /// +1 or −1.
    #[inline]
    pub fn value(self) -> f64 {
        match self {
            Sign::Plus => 1.0,
            Sign::Minus => -1.0,
        }
    }
}

impl NormalLoad {
    /// \[N\] the normal load from the normal element's force `f` (on its `body2`, local axes).
    #[inline]
    pub fn load(&self, f: [f64; 3]) -> f64 {
        match self.rule {
            NormalRule::Along { axis, sign } => (sign.value() * f[axis.index()]).max(0.0),
            NormalRule::Magnitude => (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt(),
        }
    }
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        self as usize
    }

    /// `"x"`, `"y"` or `"z"`.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }

    /// The axis named `"x"`, `"y"` or `"z"` ([`Self::name`]'s inverse).
    pub fn from_name(name: &str) -> Option<Axis> {
        [Axis::X, Axis::Y, Axis::Z]
            .into_iter()
            .find(|a| a.name() == name)
    }
}

/// A piecewise-linear force–deflection law.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceTable {
    /// \[m\] deflections, strictly increasing.
    pub deflection: Vec<f64>,
    /// \[N\] the force T(d) at each deflection, signed (body 2 receives −T(d)).
    pub force: Vec<f64>,
    /// The table is given for d ≥ 0 and mirrored: F(−d) = −F(d).
    pub symmetric: bool,
}

impl ForceTable {
    /// \[N\] force magnitude at deflection `d` \[m\]: linear interpolation, and linear
    /// extrapolation with the slope of the end intervals. The force on body 2 is minus this.
    pub fn force(&self, d: f64) -> f64 {
        if self.symmetric && d < 0.0 {
            return -self.force(-d);
        }
        crate::suspension::interpolate(&self.deflection, &self.force, d)
    }

    /// \[N/m\] slope dF/dd at `d` \[m\] (central difference over 1 µm).
    pub fn slope(&self, d: f64) -> f64 {
        let h = 1e-6;
        (self.force(d + h) - self.force(d - h)) / (2.0 * h)
    }
}

/// The law of a force element. Deflections are the motion of body 2's attachment point
/// relative to body 1's, in the element's local axes; forces are on body 2 (body 1 receives the
/// opposite).
#[derive(Debug, Clone, PartialEq)]
pub enum ForceLaw {
    /// 6-DOF linear bushing: F = −K·Δ − C·Δ̇ per local direction.
    Bushing {
        /// \[N/m, N/m, N/m, N·m/rad, N·m/rad, N·m/rad\] stiffness along x, y, z and about
        /// x, y, z.
        stiffness: [f64; 6],
        /// \[N·s/m ×3, N·m·s/rad ×3\] viscous damping, same order.
        damping: [f64; 6],
    },
    /// Nonlinear force table along one local axis: F = −table(Δ).
    Table {
        /// The local axis.
        axis: Axis,
        /// The law.
        table: ForceTable,
    },
    /// Spring k in series with damper c along one local axis. Internal state: the damper's
    /// elongation s \[m\]; F = −k·(Δ − s), ṡ = (k/c)·(Δ − s).
    SeriesSpringDamper {
        /// The local axis.
        axis: Axis,
        /// \[N/m\] series spring stiffness.
        stiffness: f64,
        /// \[N·s/m\] damper coefficient.
        damping: f64,
    },
    /// Anti-roll bar: torsional spring about the local x-axis between the two bodies' roll
    /// angles: M = −k·(φ2 − φ1) on body 2.
    AntiRollBar {
        /// \[N·m/rad\] torsional stiffness.
        stiffness: f64,
    },
    /// Damper with a force–velocity table along one local axis
    /// ([`crate::suspension::damper_series_law`]): F = −f_d(Δ̇), or with a series (mount)
    /// stiffness k an internal state, the damper's elongation s: F = −k·(Δ − s),
    /// ṡ = f_d⁻¹(k·(Δ − s)).
    Damper {
        /// The local axis.
        axis: Axis,
        /// The force–velocity law.
        table: DamperTable,
        /// \[N/m\] series stiffness (`None`: the damper acts alone, no state).
        stiffness: Option<f64>,
    },
    /// Dry friction with a stick stiffness along one local axis, or about it when `rotational`
    /// ([`crate::suspension::friction_law`]). Internal state: the slider's position s (an
    /// angle when rotational); F = −k·(Δ − s), sliding at F0 = `force` + `coefficient`·N, N the
    /// normal load from the force of another element ([`NormalLoad`]).
    Friction {
        /// The local axis.
        axis: Axis,
        /// A friction moment about `axis` (side bearers, centre pivot) instead of a force along
        /// it: the law on the rotation, the moment on the bodies.
        rotational: bool,
        /// \[N/m\] stick stiffness (\[N·m/rad\] when rotational).
        stiffness: f64,
        /// \[N\] constant part of the sliding force (\[N·m\] of the sliding moment).
        force: f64,
        /// \[-\] friction coefficient on the normal element's force (0 without one); \[m\] the
        /// coefficient times the friction radius when rotational.
        coefficient: f64,
        /// Where the normal load comes from.
        normal: Option<NormalLoad>,
    },
    /// Dry friction in the plane of two local axes with one sliding force for every direction
    /// ([`crate::suspension::planar_friction_law`]). Internal states: the slider's position
    /// along the two axes; F = −k·(Δ − s) in the plane, |k·(Δ − s)| ≤ F0 = `force` +
    /// `coefficient`·N.
    PlanarFriction {
        /// The two local axes of the plane, in the order of the states.
        axes: [Axis; 2],
        /// \[N/m\] stick stiffness, the same in every direction of the plane.
        stiffness: f64,
        /// \[N\] constant part of the sliding force.
        force: f64,
        /// \[-\] friction coefficient on the normal element's force (0 without one).
        coefficient: f64,
        /// Where the normal load comes from.
        normal: Option<NormalLoad>,
    },
}

impl ForceLaw {
    /// Whether the element is a friction element (its sliding force may depend on another
    /// element's force, which must be evaluated first).
    pub fn is_friction(&self) -> bool {
        matches!(
            self,
            ForceLaw::Friction { .. } | ForceLaw::PlanarFriction { .. }
        )
    }

    /// Whether the element dissipates energy: a bushing with some damping, a series
    /// spring-damper, a damper, a friction element. The others (springs, force tables, anti-roll
    /// bars) are conservative: the work they absorb is the change of the energy they store.
    pub fn dissipates(&self) -> bool {
        match self {
            ForceLaw::Bushing { damping, .. } => damping.iter().any(|c| *c != 0.0),
            ForceLaw::Table { .. } | ForceLaw::AntiRollBar { .. } => false,
            ForceLaw::SeriesSpringDamper { .. }
            | ForceLaw::Damper { .. }
            | ForceLaw::Friction { .. }
            | ForceLaw::PlanarFriction { .. } => true,
        }
    }

    /// The type's name as written in a vehicle file (`type = "..."`).
    pub fn type_name(&self) -> &'static str {
        match self {
            ForceLaw::Bushing { .. } => "bushing",
            ForceLaw::Table { .. } => "table",
            ForceLaw::SeriesSpringDamper { .. } => "series_spring_damper",
            ForceLaw::AntiRollBar { .. } => "anti_roll_bar",
            ForceLaw::Damper { .. } => "damper",
            ForceLaw::Friction {
                rotational: false, ..
            } => "friction",
            ForceLaw::Friction {
                rotational: true, ..
            } => "rotational_friction",
            ForceLaw::PlanarFriction { .. } => "planar_friction",
        }
    }

    /// Number of internal states the element carries: 1 for a series spring-damper, a
    /// friction element and a damper with a series stiffness, 2 for a planar friction, else 0.
    pub fn internal_states(&self) -> usize {
        if matches!(self, ForceLaw::PlanarFriction { .. }) {
            return 2;
        }
        usize::from(matches!(
            self,
            ForceLaw::SeriesSpringDamper { .. }
                | ForceLaw::Friction { .. }
                | ForceLaw::Damper {
                    stiffness: Some(_),
                    ..
                }
        ))
    }
}

/// Series spring-damper: \[N\] force on body 2 along its axis, for deflection `delta` \[m\] and
/// damper elongation `s` \[m\].
pub fn series_force(stiffness: f64, delta: f64, s: f64) -> f64 {
    -stiffness * (delta - s)
}

/// Series spring-damper: \[m/s\] rate of the damper elongation, ṡ = (k/c)·(Δ − s): the damper
/// force c·ṡ equals the spring force k·(Δ − s).
pub fn series_state_rate(stiffness: f64, damping: f64, delta: f64, s: f64) -> f64 {
    stiffness / damping * (delta - s)
}

/// A force element.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceElement {
    /// Unique name.
    pub name: String,
    /// First end.
    pub body1: Endpoint,
    /// Second end.
    pub body2: Endpoint,
    /// \[m\] attachment point on body 1, vehicle frame, nominal configuration.
    pub point1: [f64; 3],
    /// \[m\] attachment point on body 2, vehicle frame, nominal configuration.
    pub point2: [f64; 3],
    /// \[-\] rotation from local to vehicle axes (columns: local axes in the vehicle frame).
    pub axes: Mat3,
    /// The law.
    pub law: ForceLaw,
    /// The element acts along the line between its two attachment points as they move
    /// (`direction = "line"`): its deflection is the change of that distance, its force lies on
    /// the line. Its local x is the line at the nominal configuration, the law's axis x.
    pub line: bool,
}

impl ForceElement {
    /// \[m\] the distance between the two attachment points at the nominal configuration.
    pub fn nominal_length(&self) -> f64 {
        let d = [
            self.point2[0] - self.point1[0],
            self.point2[1] - self.point1[1],
            self.point2[2] - self.point1[2],
        ];
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }
}

/// An internal state variable of a force element, integrated with the vehicle's states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InternalState {
    /// The element carrying it.
    pub element: ForceElementId,
    /// What it is.
    pub kind: InternalStateKind,
}

/// Kinds of internal states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InternalStateKind {
    /// \[m\] the elongation s of the damper of a series spring-damper or of a damper with a
    /// series stiffness, from its nominal length.
    DamperElongation,
    /// \[m\] the position s of a friction element's slider (its tension is k·(Δ − s)); \[rad\]
    /// its angle for a rotational friction.
    FrictionSlip,
}

/// The compiled vehicle: immutable, SI, names resolved, shareable between threads.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleModel {
    pub(crate) name: String,
    pub(crate) source: String,
    pub(crate) gravity: f64,
    pub(crate) bodies: Vec<Body>,
    pub(crate) wheelsets: Vec<Wheelset>,
    pub(crate) forces: Vec<ForceElement>,
}

impl fmt::Display for Dof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.member {
            Member::Body(b) => write!(f, "body#{}.{}", b.0, self.kind.body_name()),
            Member::Wheelset(w) => write!(f, "wheelset#{}.{}", w.0, self.kind.wheelset_name()),
        }
    }
}

impl VehicleModel {
    /// Read and compile a vehicle file, reporting structural and range problems together.
    /// Relative profile paths are resolved from the file's directory.
    pub fn from_file(path: impl AsRef<Path>) -> Result<VehicleModel, VehicleError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| VehicleError::Io {
            file: name.clone(),
            message: e.to_string(),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        VehicleModel::from_toml_str(&text, &name, base)
    }

    /// The wheel profile files the vehicle read (resolved), each once, in wheelset order (a log
    /// records them, so that a re-run can tell when one has changed).
    pub fn data_files(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = Vec::new();
        for p in self.wheelsets.iter().flat_map(|w| &w.profiles) {
            if let WheelProfile::File(path) = p
                && !files.contains(&path.as_path())
            {
                files.push(path);
            }
        }
        files
    }

    /// Read and compile vehicle TOML text. Every problem (syntax, unknown keys, wrong types,
    /// missing keys, ranges, references) is reported in one [`VehicleError::Invalid`], sorted by
    /// position.
    pub fn from_toml_str(
        text: &str,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<VehicleModel, VehicleError> {
        let (spec, mut problems) = VehicleSpec::parse_lenient(text, source_name);
        let syntax = problems
            .iter()
            .any(|p| p.message.starts_with("TOML syntax"));
        if syntax {
            return Err(VehicleError::Invalid { problems });
        }
        match VehicleModel::compile(&spec, source_name, base_dir) {
            Ok(model) if problems.is_empty() => Ok(model),
            Ok(_) => Err(VehicleError::Invalid { problems }),
            Err(VehicleError::Invalid { problems: more }) => {
                problems.extend(more);
                problems.sort_by_key(|p| (p.line, p.col));
                Err(VehicleError::Invalid { problems })
            }
            Err(e) => Err(e),
        }
    }

    /// Compile a spec: resolve names to ids, convert to SI, check ranges and references.
    /// `source_name` prefixes every message; `base_dir` resolves relative profile paths.
    ///
    /// ```
    /// use std::path::Path;
    /// use railsim_vehicle::{VehicleModel, VehicleSpec};
    /// let text = r#"
    /// name = "one wheelset"
    /// [[wheelset]]
    /// name = "ws"
    /// mass_kg = 1813
    /// inertia_kgm2 = [1120, 112, 1120]
    /// position_m = [0, 0, 0.46]
    /// nominal_radius_m = 0.46
    /// back_to_back_mm = 1360
    /// wheel_profile = { left = "s1002", right = "s1002" }
    /// "#;
    /// let spec = VehicleSpec::from_toml_str(text, "doc.toml").unwrap();
    /// let v = VehicleModel::compile(&spec, "doc.toml", Path::new(".")).unwrap();
    /// assert_eq!(v.total_mass(), 1813.0);
    /// assert_eq!(v.dofs().len(), 6);
    /// let eq = v.static_equilibrium().unwrap();
    /// assert!((eq.wheel_loads[0][0] - 1813.0 * 9.81 / 2.0).abs() < 1e-6);
    /// ```
    pub fn compile(
        spec: &VehicleSpec,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<VehicleModel, VehicleError> {
        let mut c = Compiler {
            sink: Sink::new(source_name, &spec.source),
            dropped: &spec.dropped_keys,
            last_frozen: None,
        };
        let model = c.compile(spec, base_dir);
        if c.sink.problems.is_empty()
            && model.dofs().is_empty()
            && let Some(span) = c.last_frozen.clone()
        {
            c.err(
                &span,
                "frozen",
                "every degree of freedom of every body and wheelset is frozen, so nothing would move; expected at least one free".to_owned(),
            );
        }
        if c.sink.problems.is_empty() {
            Ok(model)
        } else {
            let mut problems = c.sink.problems;
            problems.sort_by_key(|p| (p.line, p.col));
            Err(VehicleError::Invalid { problems })
        }
    }

    /// Name of the vehicle (the file's `name`, else the source name).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The source name given to compile (usually the file path).
    pub fn source(&self) -> &str {
        &self.source
    }
    /// \[m/s²\] gravitational acceleration.
    pub fn gravity(&self) -> f64 {
        self.gravity
    }
    /// The rigid bodies, indexed by [`BodyId`].
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }
    /// The wheelsets, indexed by [`WheelsetId`].
    pub fn wheelsets(&self) -> &[Wheelset] {
        &self.wheelsets
    }
    /// The wheelsets' indices from the front (largest x first): the numbering of the
    /// simulator's logs and summaries.
    pub fn wheelsets_from_front(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.wheelsets.len()).collect();
        order.sort_by(|&a, &b| {
            self.wheelsets[b].position[0].total_cmp(&self.wheelsets[a].position[0])
        });
        order
    }
    /// The carbody: the heaviest rigid body (the last of equal masses); `None` without rigid
    /// bodies. The simulator's ride and stability assessment and `railsim statics` take it so.
    pub fn carbody(&self) -> Option<BodyId> {
        self.bodies
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.mass.total_cmp(&b.1.mass))
            .map(|(i, _)| BodyId(i))
    }
    /// The bogies: the rigid bodies other than the [`carbody`](Self::carbody) at least
    /// [`BOGIE_FRAME_MIN_OFFSET`] from it along x, each with the wheelsets nearest to it along x
    /// (the first frame of equal distances), in body order and with their wheelsets in
    /// wheelset order; a frame without wheelsets is no bogie. Empty without a carbody. The rule
    /// of the simulator's simplified stability method (bogie-frame accelerations) and of the
    /// bogie twist of `railsim statics`.
    pub fn bogies(&self) -> Vec<Bogie> {
        let Some(cb) = self.carbody() else {
            return Vec::new();
        };
        let cb_x = self.bodies[cb.index()].position[0];
        let mut bogies: Vec<Bogie> = (0..self.bodies.len())
            .filter(|&i| {
                i != cb.index()
                    && (self.bodies[i].position[0] - cb_x).abs() >= BOGIE_FRAME_MIN_OFFSET
            })
            .map(|i| Bogie {
                frame: BodyId(i),
                wheelsets: Vec::new(),
            })
            .collect();
        for (i, w) in self.wheelsets.iter().enumerate() {
            let dx = |g: &Bogie| (self.bodies[g.frame.index()].position[0] - w.position[0]).abs();
            if let Some(g) = bogies.iter_mut().min_by(|a, b| dx(a).total_cmp(&dx(b))) {
                g.wheelsets.push(WheelsetId(i));
            }
        }
        bogies.retain(|g| !g.wheelsets.is_empty());
        bogies
    }
    /// Removes every wheel's out-of-roundness (for the studies of steady states and of
    /// linearisations, which remove the track's irregularities too).
    pub fn make_wheels_round(&mut self) {
        for w in &mut self.wheelsets {
            w.out_of_roundness = Default::default();
        }
    }
    /// The force elements, indexed by [`ForceElementId`].
    pub fn forces(&self) -> &[ForceElement] {
        &self.forces
    }
    /// A body by id.
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.0]
    }
    /// A wheelset by id.
    pub fn wheelset(&self, id: WheelsetId) -> &Wheelset {
        &self.wheelsets[id.0]
    }
    /// A force element by id.
    pub fn force(&self, id: ForceElementId) -> &ForceElement {
        &self.forces[id.0]
    }
    /// The id of the body called `name`.
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }
    /// The id of the wheelset called `name`.
    pub fn wheelset_id(&self, name: &str) -> Option<WheelsetId> {
        self.wheelsets
            .iter()
            .position(|w| w.name == name)
            .map(WheelsetId)
    }
    /// The id of the force element called `name`.
    pub fn force_id(&self, name: &str) -> Option<ForceElementId> {
        self.forces
            .iter()
            .position(|f| f.name == name)
            .map(ForceElementId)
    }
    /// Name of a member.
    pub fn member_name(&self, m: Member) -> &str {
        match m {
            Member::Body(b) => &self.bodies[b.0].name,
            Member::Wheelset(w) => &self.wheelsets[w.0].name,
        }
    }
    /// Name of a degree of freedom, e.g. `carbody.roll` or `ws1.spin`.
    pub fn dof_name(&self, d: Dof) -> String {
        match d.member {
            Member::Body(b) => format!("{}.{}", self.bodies[b.0].name, d.kind.body_name()),
            Member::Wheelset(w) => {
                format!("{}.{}", self.wheelsets[w.0].name, d.kind.wheelset_name())
            }
        }
    }

    /// \[kg\] total mass of bodies and wheelsets.
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum::<f64>()
            + self.wheelsets.iter().map(|w| w.mass).sum::<f64>()
    }

    /// The degrees of freedom the simulation needs: six per body and wheelset (bodies first,
    /// in file order; x, y, z, roll, pitch/spin, yaw), frozen ones excluded.
    pub fn dofs(&self) -> Vec<Dof> {
        let mut out = Vec::new();
        for (i, b) in self.bodies.iter().enumerate() {
            for k in DofKind::ALL {
                if !b.frozen[k.index()] {
                    out.push(Dof {
                        member: Member::Body(BodyId(i)),
                        kind: k,
                    });
                }
            }
        }
        for (i, w) in self.wheelsets.iter().enumerate() {
            for k in DofKind::ALL {
                if !w.frozen[k.index()] {
                    out.push(Dof {
                        member: Member::Wheelset(WheelsetId(i)),
                        kind: k,
                    });
                }
            }
        }
        out
    }

    /// The internal states of the force elements (one per series spring-damper, friction
    /// element and damper with a series stiffness, two per planar friction), in element order.
    pub fn internal_states(&self) -> Vec<InternalState> {
        self.forces
            .iter()
            .enumerate()
            .flat_map(|(i, f)| {
                let kind = if f.law.is_friction() {
                    InternalStateKind::FrictionSlip
                } else {
                    InternalStateKind::DamperElongation
                };
                (0..f.law.internal_states()).map(move |_| InternalState {
                    element: ForceElementId(i),
                    kind,
                })
            })
            .collect()
    }
}

/// The keys of a friction element's sliding limit (`Compiler::friction_limit`).
fn friction_limit_keys(rotational: bool) -> Vec<&'static str> {
    if rotational {
        vec![
            "friction_moment_nm",
            "friction_coefficient",
            "normal_element",
            "normal_direction",
            "friction_radius_m",
        ]
    } else {
        vec![
            "friction_force_n",
            "friction_coefficient",
            "normal_element",
            "normal_direction",
        ]
    }
}

/// The plausible upper bound and the unit of a stiffness or damping key (`None` for other keys).
fn upper_bound(key: &str) -> Option<(f64, &'static str)> {
    match key {
        "stiffness_n_per_m" => Some((MAX_STIFFNESS, "N/m")),
        "rotational_stiffness_nm_per_rad" => Some((MAX_ROTATIONAL_STIFFNESS, "N·m/rad")),
        "damping_ns_per_m" => Some((MAX_DAMPING, "N·s/m")),
        "rotational_damping_nms_per_rad" => Some((MAX_ROTATIONAL_DAMPING, "N·m·s/rad")),
        _ => None,
    }
}

/// What to do about a stiffness or damping above its bound, for a message.
fn bound_remedy(key: &str) -> &'static str {
    if key.contains("stiffness") {
        "check the unit; to hold a degree of freedom rigid, freeze it instead"
    } else {
        "check the unit"
    }
}

/// A computed number for a message, to 4 significant digits (`1.667e-7`, `100`, not
/// `100.00000000000001`).
fn computed(x: f64) -> String {
    short_number(format!("{x:.3e}").parse().unwrap_or(x))
}

/// Centre of gravity \[m\] and largest distance \[m\] of an attachment point from it.
type Reach = ([f64; 3], f64);

/// A table's points for [`Compiler::table_slopes`]: abscissae in file units (`x_scale` turns
/// them into SI), values in N and the span of each value.
struct TableSlopes<'a> {
    /// Abscissae, file units.
    x: &'a [f64],
    /// \[SI per file unit\] 1e-3 for mm.
    x_scale: f64,
    /// \[N\] values.
    y: &'a [f64],
    /// Span of each value (an added origin takes the first one's).
    spans: &'a [Range<usize>],
    /// Key of the abscissae.
    x_key: &'a str,
    /// Unit of the abscissae in the file.
    x_unit: &'a str,
    /// \[N/m or N·s/m\] largest slope.
    max: f64,
    /// Unit of the slope.
    slope_unit: &'a str,
}

/// The compile pass: one sink, every problem recorded.
struct Compiler<'a> {
    sink: Sink<'a>,
    dropped: &'a [(usize, String)],
    /// the last `frozen` list read (where a vehicle with nothing free is reported)
    last_frozen: Option<Range<usize>>,
}

fn is_dropped(dropped: &[(usize, String)], table: &Range<usize>, key: &str) -> bool {
    dropped.iter().any(|(s, k)| *s == table.start && k == key)
}

impl Compiler<'_> {
    fn err(&mut self, span: &Range<usize>, key: &str, message: String) {
        self.sink.at(Some(span), key, message);
    }

    /// A required key: report it missing (unless dropped for a wrong type).
    fn req<'s, T>(
        &mut self,
        v: &'s Option<Spanned<T>>,
        table: &Range<usize>,
        label: &str,
        key: &str,
        expected: &str,
    ) -> Option<&'s Spanned<T>> {
        if v.is_none() && !is_dropped(self.dropped, table, key) {
            self.err(
                table,
                key,
                format!("{label}: missing key '{key}' (expected {expected})"),
            );
        }
        v.as_ref()
    }

    fn finite3(&mut self, v: &Spanned<[f64; 3]>, label: &str, key: &str) -> Option<[f64; 3]> {
        let a = *v.get_ref();
        if a.iter().all(|x| x.is_finite()) {
            Some(a)
        } else {
            self.err(
                &v.span(),
                key,
                format!("{label}: {key} must be finite numbers, found {a:?}"),
            );
            None
        }
    }

    fn positive(&mut self, v: &Spanned<f64>, label: &str, key: &str, unit: &str) -> Option<f64> {
        let x = *v.get_ref();
        if x.is_finite() && x > 0.0 {
            Some(x)
        } else {
            self.err(
                &v.span(),
                key,
                format!("{label}: {key} must be a positive number of {unit}, found {x}"),
            );
            None
        }
    }

    /// Whether every value of a stiffness or damping key is within its plausible bound
    /// ([`upper_bound`]); reports the first one above it.
    fn within_bound(&mut self, v: &Range<usize>, values: &[f64], label: &str, key: &str) -> bool {
        let Some((max, unit)) = upper_bound(key) else {
            return true;
        };
        let Some(x) = values.iter().find(|x| **x > max) else {
            return true;
        };
        let shown = if values.len() == 1 {
            String::new()
        } else {
            format!(" {values:?}:")
        };
        self.err(
            v,
            key,
            format!(
                "{label}: {key}{shown} {} {unit} is implausible (expected at most {} {unit}; {})",
                short_number(*x),
                short_number(max),
                bound_remedy(key)
            ),
        );
        false
    }

    fn compile(&mut self, spec: &VehicleSpec, base_dir: &Path) -> VehicleModel {
        let name = spec
            .name
            .as_ref()
            .map_or_else(|| self.sink.file.to_owned(), |n| n.get_ref().clone());
        let gravity = match &spec.gravity_m_per_s2 {
            None => DEFAULT_GRAVITY,
            Some(g) => {
                let x = *g.get_ref();
                if x.is_finite() && x > 0.0 && x <= 30.0 {
                    x
                } else {
                    self.err(
                        &g.span(),
                        "gravity_m_per_s2",
                        format!("gravity_m_per_s2 must lie in (0, 30] m/s², found {x}"),
                    );
                    DEFAULT_GRAVITY
                }
            }
        };

        // Names of bodies and wheelsets share one namespace (force elements refer to both).
        let mut names: Vec<(String, Range<usize>)> = Vec::new();
        let mut bodies = Vec::new();
        for b in &spec.body {
            if let Some(body) = self.body(b.get_ref(), &b.span(), &mut names) {
                bodies.push(body);
            }
        }
        let mut wheelsets: Vec<Wheelset> = Vec::new();
        for w in &spec.wheelset {
            if let Some(ws) = self.wheelset(w.get_ref(), &w.span(), &mut names, &bodies, base_dir) {
                // Two wheelsets closer along the vehicle than their wheels' diameters would
                // share the rails' contact points (a copied table whose position was not
                // changed).
                let clash = wheelsets.iter().find(|o| {
                    (o.position[0] - ws.position[0]).abs() < o.nominal_radius + ws.nominal_radius
                });
                if let (Some(o), Some(v)) = (clash, &w.get_ref().position_m) {
                    self.err(
                        &v.span(),
                        "position_m",
                        format!(
                            "wheelset '{}': position_m x = {} m is {} m from wheelset '{}' (x = {} m); expected wheelsets at least their wheels' radii apart ({} m)",
                            ws.name,
                            short_number(ws.position[0]),
                            short_number((o.position[0] - ws.position[0]).abs()),
                            o.name,
                            short_number(o.position[0]),
                            short_number(o.nominal_radius + ws.nominal_radius)
                        ),
                    );
                    continue;
                }
                wheelsets.push(ws);
            }
        }
        if spec.wheelset.is_empty() {
            self.err(
                &(0..0),
                "wheelset",
                "a vehicle needs at least one [[wheelset]]".to_owned(),
            );
        }
        // Bodies that were declared but failed their own checks are not reported again as
        // unknown when a force element refers to them.
        let mut known_bad: Vec<String> = spec.unreadable_names.clone();
        known_bad.extend(names.iter().map(|(n, _)| n.clone()));
        let mut force_names: Vec<(String, Range<usize>)> = Vec::new();
        let mut forces = Vec::new();
        for f in &spec.force {
            if let Some(fe) = self.force(
                f.get_ref(),
                &f.span(),
                &mut force_names,
                &bodies,
                &wheelsets,
                &known_bad,
            ) {
                forces.push(fe);
            }
        }
        self.resolve_normals(spec, &mut forces);
        VehicleModel {
            name,
            source: self.sink.file.to_owned(),
            gravity,
            bodies,
            wheelsets,
            forces,
        }
    }

    fn name(
        &mut self,
        v: &Option<Spanned<String>>,
        table: &Range<usize>,
        what: &str,
        names: &mut Vec<(String, Range<usize>)>,
    ) -> Option<String> {
        let n = self.req(v, table, what, "name", "a unique name")?;
        let s = n.get_ref().trim().to_owned();
        if s.is_empty() {
            self.err(&n.span(), "name", format!("{what}: name must not be empty"));
            return None;
        }
        if s == TRACK {
            self.err(
                &n.span(),
                "name",
                format!("{what}: name '{TRACK}' is reserved for the track-following frame"),
            );
            return None;
        }
        if let Some((_, first)) = names.iter().find(|(m, _)| *m == s) {
            let (l, c) = self.sink.map.line_col(first.start);
            self.err(
                &n.span(),
                "name",
                format!(
                    "{what} '{s}': duplicate name '{s}' (first defined at line {l}, column {c})"
                ),
            );
            return None;
        }
        names.push((s.clone(), n.span()));
        Some(s)
    }

    /// Mass, inertia tensor, position and frozen list, common to bodies and wheelsets.
    #[allow(clippy::type_complexity)]
    fn rigid(
        &mut self,
        label: &str,
        table: &Range<usize>,
        mass: &Option<Spanned<f64>>,
        inertia: &Option<Spanned<[f64; 3]>>,
        products: &Option<Spanned<[f64; 3]>>,
        position: &Option<Spanned<[f64; 3]>>,
        frozen: &Option<Spanned<Vec<Spanned<String>>>>,
        dof_names: &[&str; 6],
    ) -> (Option<f64>, Option<Mat3>, Option<[f64; 3]>, [bool; 6]) {
        let m = self
            .req(mass, table, label, "mass_kg", "a positive mass in kg")
            .and_then(|v| self.positive(v, label, "mass_kg", "kg"));
        if let (Some(x), Some(v)) = (m, mass)
            && !(MASS_RANGE.0..=MASS_RANGE.1).contains(&x)
        {
            self.err(
                &v.span(),
                "mass_kg",
                format!(
                    "{label}: mass_kg = {} kg is implausible for one body (expected {} to {} kg)",
                    short_number(x),
                    MASS_RANGE.0,
                    short_number(MASS_RANGE.1)
                ),
            );
        }
        let inertia = self
            .req(
                inertia,
                table,
                label,
                "inertia_kgm2",
                "[Ixx, Iyy, Izz] in kg·m²",
            )
            .and_then(|v| self.inertia(v, products.as_ref(), label));
        let pos = self
            .req(position, table, label, "position_m", "[x, y, z] in m")
            .and_then(|v| self.finite3(v, label, "position_m"));
        if let (Some(p), Some(v)) = (pos, position)
            && (p[1].abs() > MAX_HALF_WIDTH || p[2] < Z_RANGE.0 || p[2] > Z_RANGE.1)
        {
            self.err(
                &v.span(),
                "position_m",
                format!(
                    "{label}: position_m {p:?} is implausible (expected |y| <= {MAX_HALF_WIDTH} m and z in [{}, {}] m)",
                    Z_RANGE.0, Z_RANGE.1
                ),
            );
        }
        let mut fz = [false; 6];
        if let Some(list) = frozen {
            self.last_frozen = Some(list.span());
            for item in list.get_ref() {
                let s = item.get_ref().as_str();
                match dof_names.iter().position(|d| *d == s) {
                    Some(i) if fz[i] => self.err(
                        &item.span(),
                        "frozen",
                        format!("{label}: frozen lists '{s}' twice"),
                    ),
                    Some(i) => fz[i] = true,
                    None => self.err(
                        &item.span(),
                        "frozen",
                        format!(
                            "{label}: frozen: unknown degree of freedom '{s}'{}; expected one of: {}",
                            did_you_mean(s, dof_names.iter().copied()),
                            dof_names.join(", ")
                        ),
                    ),
                }
            }
        }
        (m, inertia, pos, fz)
    }

    fn inertia(
        &mut self,
        v: &Spanned<[f64; 3]>,
        products: Option<&Spanned<[f64; 3]>>,
        label: &str,
    ) -> Option<Mat3> {
        let d = self.finite3(v, label, "inertia_kgm2")?;
        let p = match products {
            Some(p) => self.finite3(p, label, "products_kgm2")?,
            None => [0.0; 3],
        };
        let t = [[d[0], p[0], p[1]], [p[0], d[1], p[2]], [p[1], p[2], d[2]]];
        let span = products.map_or_else(|| v.span(), |p| p.span());
        let key = if products.is_some() {
            "products_kgm2"
        } else {
            "inertia_kgm2"
        };
        if let Some(x) = d.iter().find(|x| **x > MAX_INERTIA) {
            self.err(
                &v.span(),
                "inertia_kgm2",
                format!(
                    "{label}: inertia_kgm2 {d:?}: {} kg·m² is implausible for one body (expected at most {} kg·m²)",
                    short_number(*x),
                    short_number(MAX_INERTIA)
                ),
            );
            return None;
        }
        if d.iter().any(|x| *x <= 0.0) {
            self.err(
                &v.span(),
                "inertia_kgm2",
                format!(
                    "{label}: inertia_kgm2 {d:?} is not positive definite (every moment must be > 0 kg·m²)"
                ),
            );
            return None;
        }
        if let Some(x) = d.iter().find(|x| **x < MIN_INERTIA) {
            self.err(
                &v.span(),
                "inertia_kgm2",
                format!(
                    "{label}: inertia_kgm2 {d:?}: {} kg·m² is implausible (expected at least {} kg·m²; in kg·m², not t·m²?)",
                    short_number(*x),
                    short_number(MIN_INERTIA)
                ),
            );
            return None;
        }
        let mut a: Vec<f64> = t.iter().flatten().copied().collect();
        if cholesky(&mut a, 3).is_err() {
            self.err(
                &span,
                key,
                format!(
                    "{label}: inertia tensor (inertia_kgm2 {d:?}, products_kgm2 {p:?}) is not positive definite"
                ),
            );
            return None;
        }
        let e = sym3_eigenvalues(&t);
        let tol = 1e-9 * e[2];
        if e[0] + e[1] < e[2] - tol {
            self.err(
                &span,
                key,
                format!(
                    "{label}: {key}: principal moments {e:.6?} kg·m² violate the triangle inequality I1 + I2 >= I3 (no rigid body has them)"
                ),
            );
            return None;
        }
        Some(t)
    }

    fn body(
        &mut self,
        b: &BodySpec,
        table: &Range<usize>,
        names: &mut Vec<(String, Range<usize>)>,
    ) -> Option<Body> {
        let name = self.name(&b.name, table, "body", names);
        let label = name
            .as_ref()
            .map_or_else(|| "body".to_owned(), |n| format!("body '{n}'"));
        let dof_names = DofKind::ALL.map(DofKind::body_name);
        let (mass, inertia, position, frozen) = self.rigid(
            &label,
            table,
            &b.mass_kg,
            &b.inertia_kgm2,
            &b.products_kgm2,
            &b.position_m,
            &b.frozen,
            &dof_names,
        );
        Some(Body {
            name: name?,
            mass: mass?,
            inertia: inertia?,
            position: position?,
            frozen,
        })
    }

    fn wheelset(
        &mut self,
        w: &WheelsetSpec,
        table: &Range<usize>,
        names: &mut Vec<(String, Range<usize>)>,
        bodies: &[Body],
        base_dir: &Path,
    ) -> Option<Wheelset> {
        let name = self.name(&w.name, table, "wheelset", names);
        let label = name
            .as_ref()
            .map_or_else(|| "wheelset".to_owned(), |n| format!("wheelset '{n}'"));
        let dof_names = DofKind::ALL.map(DofKind::wheelset_name);
        let (mass, inertia, position, frozen) = self.rigid(
            &label,
            table,
            &w.mass_kg,
            &w.inertia_kgm2,
            &w.products_kgm2,
            &w.position_m,
            &w.frozen,
            &dof_names,
        );
        // The dynamics treats a wheelset as an axisymmetric rotor (docs/models/dynamics.md): its
        // products of inertia would be silently dropped, so they are refused.
        if let Some(p) = &w.products_kgm2
            && p.get_ref().iter().any(|&x| x != 0.0)
        {
            self.err(
                &p.span(),
                "products_kgm2",
                format!(
                    "{label}: products_kgm2 = {:?} is not used for a wheelset (modelled as an \
                     axisymmetric rotor); expected no products_kgm2 or [0, 0, 0]",
                    p.get_ref()
                ),
            );
        }
        let r0 = self
            .req(
                &w.nominal_radius_m,
                table,
                &label,
                "nominal_radius_m",
                "a positive radius in m",
            )
            .and_then(|v| self.positive(v, &label, "nominal_radius_m", "m"));
        if let (Some(r), Some(v)) = (r0, &w.nominal_radius_m)
            && !(0.1..=1.0).contains(&r)
        {
            self.err(
                &v.span(),
                "nominal_radius_m",
                format!(
                    "{label}: nominal_radius_m = {r} m is implausible (expected 0.1 to 1.0 m; the file unit is m, not mm)"
                ),
            );
        }
        if let (Some(r), Some(p), Some(v)) = (r0, position, &w.position_m) {
            if (p[2] - r).abs() > 0.005 {
                self.err(
                    &v.span(),
                    "position_m",
                    format!(
                        "{label}: position_m z = {} m must equal nominal_radius_m = {r} m (axle centre above the rail plane), within 5 mm",
                        p[2]
                    ),
                );
            }
            if p[1].abs() > 0.05 {
                self.err(
                    &v.span(),
                    "position_m",
                    format!(
                        "{label}: position_m y = {} m: a wheelset's nominal lateral position must be within 0.05 m of the track centre",
                        p[1]
                    ),
                );
            }
        }
        let b2b = self
            .req(
                &w.back_to_back_mm,
                table,
                &label,
                "back_to_back_mm",
                "the flange-back distance in mm, e.g. 1360",
            )
            .and_then(|v| self.positive(v, &label, "back_to_back_mm", "mm"));
        if let (Some(b), Some(v)) = (b2b, &w.back_to_back_mm)
            && !(500.0..=2000.0).contains(&b)
        {
            self.err(
                &v.span(),
                "back_to_back_mm",
                format!(
                    "{label}: back_to_back_mm = {b} mm is implausible (expected 500 to 2000 mm)"
                ),
            );
        }
        let rc = match &w.running_circle_from_back_mm {
            None => Some(70.0),
            Some(v) => {
                let x = *v.get_ref();
                if x.is_finite() && (0.0..=200.0).contains(&x) {
                    Some(x)
                } else {
                    self.err(
                        &v.span(),
                        "running_circle_from_back_mm",
                        format!("{label}: running_circle_from_back_mm must lie in [0, 200] mm, found {x}"),
                    );
                    None
                }
            }
        };
        let torque = match &w.torque_nm {
            None => Some(0.0),
            Some(v) if v.get_ref().is_finite() && v.get_ref().abs() <= MAX_AXLE_TORQUE => {
                Some(*v.get_ref())
            }
            Some(v) => {
                self.err(
                    &v.span(),
                    "torque_nm",
                    format!(
                        "{label}: torque_nm = {} is implausible, expected within ±{} N·m (a locomotive's axle torque is some tens of kN·m)",
                        short_number(*v.get_ref()),
                        short_number(MAX_AXLE_TORQUE)
                    ),
                );
                None
            }
        };
        // The reaction's body: one of the rigid bodies (a wheelset's own torque cannot react
        // on a wheelset, and the track is outside the vehicle).
        let torque_reaction = match &w.torque_reaction {
            None => Some(None),
            Some(v) => {
                let name = v.get_ref().as_str();
                match bodies.iter().position(|b| b.name == name) {
                    Some(i) => Some(Some(BodyId(i))),
                    None => {
                        self.err(
                            &v.span(),
                            "torque_reaction",
                            format!(
                                "{label}: torque_reaction = \"{name}\" must name a body (the motor's or brake's mount, e.g. a bogie frame){}",
                                did_you_mean(name, bodies.iter().map(|b| b.name.as_str()))
                            ),
                        );
                        None
                    }
                }
            }
        };
        let out_of_roundness = self.out_of_roundness(&w.out_of_roundness, &label);
        let profiles = self
            .req(
                &w.wheel_profile,
                table,
                &label,
                "wheel_profile",
                "{ left = \"s1002\", right = \"s1002\" } or file paths",
            )
            .and_then(|p| {
                let p = p.get_ref();
                let l = self.profile(&p.left, &label, "wheel_profile.left", base_dir);
                let r = self.profile(&p.right, &label, "wheel_profile.right", base_dir);
                Some([l?, r?])
            });
        Some(Wheelset {
            name: name?,
            mass: mass?,
            inertia: inertia?,
            position: position?,
            nominal_radius: r0?,
            back_to_back: b2b? * 1e-3,
            running_circle_from_back: rc? * 1e-3,
            profiles: profiles?,
            torque: torque?,
            torque_reaction: torque_reaction?,
            frozen,
            out_of_roundness: out_of_roundness?,
        })
    }

    /// `[[wheelset.out_of_roundness]]`: each entry's type, side and its type's keys in range.
    fn out_of_roundness(
        &mut self,
        v: &Option<Spanned<Vec<Spanned<OutOfRoundnessSpec>>>>,
        label: &str,
    ) -> Option<[Vec<WheelDefect>; 2]> {
        let mut out: [Vec<WheelDefect>; 2] = Default::default();
        let Some(list) = v else {
            return Some(out);
        };
        let mut ok = true;
        for (i, e) in list.get_ref().iter().enumerate() {
            let at = e.span();
            let e = e.get_ref();
            let lab = format!("{label}: out_of_roundness {}", i + 1);
            let Some(kind) = self.req(&e.kind, &at, &lab, "type", "\"harmonic\" or \"flat\"")
            else {
                ok = false;
                continue;
            };
            let sides: Option<&[usize]> = match self.req(
                &e.side,
                &at,
                &lab,
                "side",
                "\"left\", \"right\" or \"both\"",
            ) {
                None => None,
                Some(s) => match s.get_ref().trim() {
                    "left" => Some(&[0]),
                    "right" => Some(&[1]),
                    "both" => Some(&[0, 1]),
                    other => {
                        self.err(
                            &s.span(),
                            "side",
                            format!("{lab}: side = \"{other}\"; expected \"left\", \"right\" or \"both\""),
                        );
                        None
                    }
                },
            };
            // a required number in (lo, hi]
            let num = |me: &mut Self,
                       v: &Option<Spanned<f64>>,
                       key: &str,
                       (lo, hi): (f64, f64),
                       unit: &str|
             -> Option<f64> {
                let v = me.req(
                    v,
                    &at,
                    &lab,
                    key,
                    &format!("a number in ({lo}, {hi}] {unit}"),
                )?;
                let x = *v.get_ref();
                if x.is_finite() && x > lo && x <= hi {
                    Some(x)
                } else {
                    me.err(
                        &v.span(),
                        key,
                        format!("{lab}: {key} = {x}; expected a number in ({lo}, {hi}] {unit}"),
                    );
                    None
                }
            };
            let angle = |me: &mut Self, v: &Option<Spanned<f64>>, key: &str| -> Option<f64> {
                match v {
                    None => Some(0.0),
                    Some(v) if v.get_ref().is_finite() && v.get_ref().abs() <= 360.0 => {
                        Some(v.get_ref().to_radians())
                    }
                    Some(v) => {
                        me.err(
                            &v.span(),
                            key,
                            format!(
                                "{lab}: {key} = {}; expected an angle within ±360 deg",
                                v.get_ref()
                            ),
                        );
                        None
                    }
                }
            };
            let foreign = |me: &mut Self, keys: [(&str, bool); 3], kind: &str| {
                let mut clean = true;
                for (key, given) in keys {
                    if given {
                        me.err(
                            &at,
                            key,
                            format!("{lab}: {key} does not apply to type = \"{kind}\""),
                        );
                        clean = false;
                    }
                }
                clean
            };
            let defect = match kind.get_ref().trim() {
                "harmonic" => {
                    let clean = foreign(
                        self,
                        [
                            ("length_mm", e.length_mm.is_some()),
                            ("depth_mm", e.depth_mm.is_some()),
                            ("position_deg", e.position_deg.is_some()),
                        ],
                        "harmonic",
                    );
                    let order = num(self, &e.order, "order", (0.0, 100.0), "waves").and_then(|n| {
                        if n.fract() == 0.0 {
                            Some(n as u32)
                        } else {
                            self.err(
                                &at,
                                "order",
                                format!("{lab}: order = {n}; expected a whole number of waves"),
                            );
                            None
                        }
                    });
                    let amplitude = num(self, &e.amplitude_mm, "amplitude_mm", (0.0, 5.0), "mm");
                    let phase = angle(self, &e.phase_deg, "phase_deg");
                    match (clean, order, amplitude, phase) {
                        (true, Some(order), Some(a), Some(phase)) => Some(WheelDefect::Harmonic {
                            order,
                            amplitude: a * 1e-3,
                            phase,
                        }),
                        _ => None,
                    }
                }
                "flat" => {
                    let clean = foreign(
                        self,
                        [
                            ("order", e.order.is_some()),
                            ("amplitude_mm", e.amplitude_mm.is_some()),
                            ("phase_deg", e.phase_deg.is_some()),
                        ],
                        "flat",
                    );
                    let length = num(self, &e.length_mm, "length_mm", (0.0, 300.0), "mm");
                    let depth = num(self, &e.depth_mm, "depth_mm", (0.0, 5.0), "mm");
                    let position = angle(self, &e.position_deg, "position_deg");
                    match (clean, length, depth, position) {
                        (true, Some(l), Some(d), Some(position)) => Some(WheelDefect::Flat {
                            length: l * 1e-3,
                            depth: d * 1e-3,
                            position,
                        }),
                        _ => None,
                    }
                }
                other => {
                    self.err(
                        &kind.span(),
                        "type",
                        format!("{lab}: type = \"{other}\"; expected \"harmonic\" or \"flat\""),
                    );
                    None
                }
            };
            match (defect, sides) {
                (Some(d), Some(sides)) => {
                    for &k in sides {
                        out[k].push(d);
                    }
                }
                _ => ok = false,
            }
        }
        ok.then_some(out)
    }

    fn profile(
        &mut self,
        v: &Spanned<String>,
        label: &str,
        key: &str,
        base_dir: &Path,
    ) -> Option<WheelProfile> {
        let s = v.get_ref().trim();
        if s.eq_ignore_ascii_case("s1002") {
            return Some(WheelProfile::S1002);
        }
        if let Some(rest) = s.strip_prefix("cone:") {
            return match rest.trim().parse::<f64>() {
                Ok(x) if x > 0.0 && x <= 1.0 => Some(WheelProfile::Cone { conicity: x }),
                _ => {
                    self.err(
                        &v.span(),
                        key,
                        format!("{label}: {key} '{s}': a cone takes its conicity in (0, 1], e.g. \"cone:0.15\""),
                    );
                    None
                }
            };
        }
        let path = base_dir.join(s);
        if !s.is_empty() && path.is_file() {
            return Some(WheelProfile::File(path));
        }
        self.err(
            &v.span(),
            key,
            format!(
                "{label}: {key} '{s}' is neither a built-in profile ({}, cone:λ) nor a file (looked for {}){}",
                BUILTIN_WHEEL_PROFILES.join(", "),
                path.display(),
                did_you_mean(s, BUILTIN_WHEEL_PROFILES)
            ),
        );
        None
    }

    fn endpoint(
        &mut self,
        v: &Option<Spanned<String>>,
        table: &Range<usize>,
        label: &str,
        key: &str,
        bodies: &[Body],
        wheelsets: &[Wheelset],
        unreadable: &[String],
    ) -> Option<(Endpoint, Option<Reach>)> {
        let n = self.req(
            v,
            table,
            label,
            key,
            "a body or wheelset name, or \"track\"",
        )?;
        let s = n.get_ref().as_str();
        if s == TRACK {
            return Some((Endpoint::Track, None));
        }
        if let Some(i) = bodies.iter().position(|b| b.name == s) {
            return Some((
                Endpoint::Member(Member::Body(BodyId(i))),
                Some((bodies[i].position, MAX_REACH_BODY)),
            ));
        }
        if let Some(i) = wheelsets.iter().position(|w| w.name == s) {
            return Some((
                Endpoint::Member(Member::Wheelset(WheelsetId(i))),
                Some((wheelsets[i].position, MAX_REACH_WHEELSET)),
            ));
        }
        // A body that exists but failed its own checks, or could not be read, is not reported
        // again: its problems are already listed.
        let known_bad = unreadable.iter().any(|u| u == s);
        if !known_bad {
            // Suggest among every declared name, also those whose element failed its checks.
            let candidates: Vec<&str> = bodies
                .iter()
                .map(|b| b.name.as_str())
                .chain(wheelsets.iter().map(|w| w.name.as_str()))
                .chain(unreadable.iter().map(|u| u.as_str()))
                .chain([TRACK])
                .collect();
            self.err(
                &n.span(),
                key,
                format!(
                    "{label}: {key} refers to unknown body '{s}'{}",
                    did_you_mean(s, candidates.iter().copied())
                ),
            );
        }
        None
    }

    fn force(
        &mut self,
        f: &ForceSpec,
        table: &Range<usize>,
        names: &mut Vec<(String, Range<usize>)>,
        bodies: &[Body],
        wheelsets: &[Wheelset],
        unreadable: &[String],
    ) -> Option<ForceElement> {
        let name = self.name(&f.name, table, "force", names);
        let label = name
            .as_ref()
            .map_or_else(|| "force".to_owned(), |n| format!("force '{n}'"));
        const KINDS: [&str; 8] = [
            "bushing",
            "table",
            "series_spring_damper",
            "damper",
            "friction",
            "planar_friction",
            "rotational_friction",
            "anti_roll_bar",
        ];
        let kind = self
            .req(&f.kind, table, &label, "type", &KINDS.join(", "))
            .and_then(|k| {
                let s = k.get_ref().as_str();
                if KINDS.contains(&s) {
                    Some(s)
                } else {
                    self.err(
                        &k.span(),
                        "type",
                        format!(
                            "{label}: unknown type '{s}'{}; expected one of: {}",
                            did_you_mean(s, KINDS),
                            KINDS.join(", ")
                        ),
                    );
                    None
                }
            });
        let e1 = self.endpoint(
            &f.body1, table, &label, "body1", bodies, wheelsets, unreadable,
        );
        let e2 = self.endpoint(
            &f.body2, table, &label, "body2", bodies, wheelsets, unreadable,
        );
        if let (Some((a, _)), Some((b, _)), Some(v)) = (&e1, &e2, &f.body2)
            && a == b
        {
            self.err(
                &v.span(),
                "body2",
                format!(
                    "{label}: body1 and body2 are the same ('{}'); a force element joins two different bodies",
                    v.get_ref()
                ),
            );
        }
        let p1 = self
            .req(&f.point_m, table, &label, "point_m", "[x, y, z] in m")
            .and_then(|v| self.finite3(v, &label, "point_m"));
        let p2 = match &f.point2_m {
            None => p1,
            Some(v) => self.finite3(v, &label, "point2_m"),
        };
        for (i, (p, end, key, value)) in [
            (p1, &e1, "point_m", &f.point_m),
            (p2, &e2, "point2_m", &f.point2_m),
        ]
        .into_iter()
        .enumerate()
        {
            let (Some(p), Some(v)) = (p, value.as_ref().or(f.point_m.as_ref())) else {
                continue;
            };
            let key = if value.is_some() { key } else { "point_m" };
            if p[1].abs() > MAX_HALF_WIDTH || p[2] < Z_RANGE.0 || p[2] > Z_RANGE.1 {
                // (body 2's end without point2_m is point_m again: reported once)
                if i == 1 && value.is_none() {
                    continue;
                }
                self.err(
                    &v.span(),
                    key,
                    format!(
                        "{label}: {key} {p:?} is implausible (expected |y| <= {MAX_HALF_WIDTH} m and z in [{}, {}] m)",
                        Z_RANGE.0, Z_RANGE.1
                    ),
                );
            } else if let Some((_, Some((c, reach)))) = end {
                let d =
                    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt();
                if d > *reach {
                    self.err(
                        &v.span(),
                        key,
                        format!(
                            "{label}: {key} {p:?} lies {d:.2} m from the centre of gravity {c:?} of the body it attaches (at most {reach} m expected)"
                        ),
                    );
                }
            }
        }
        let line = f.direction.as_ref().filter(|d| d.get_ref() == "line");
        let axes = match (&f.orientation_deg, line) {
            (_, Some(d)) => self.line_axes(f, d, p1, p2, &label),
            (None, None) => Some(rotation_rpy(0.0, 0.0, 0.0)),
            (Some(v), None) => self
                .finite3(v, &label, "orientation_deg")
                .map(|a| rotation_rpy(a[0].to_radians(), a[1].to_radians(), a[2].to_radians())),
        };
        let law = kind.and_then(|k| self.law(k, f, table, &label));
        let (e1, e2) = (e1?.0, e2?.0);
        if e1 == e2 {
            return None;
        }
        Some(ForceElement {
            name: name?,
            body1: e1,
            body2: e2,
            point1: p1?,
            point2: p2?,
            axes: axes?,
            law: law?,
            line: line.is_some(),
        })
    }

    /// The local axes of an element along the line between its points (`direction = "line"`,
    /// span `d`): x along `p2 − p1` at the nominal configuration, y horizontal (the vehicle's y
    /// for a vertical line), z = x × y. Needs `point2_m` at least 1 cm from `point_m`, no
    /// `orientation_deg`, and a one-axis type.
    fn line_axes(
        &mut self,
        f: &ForceSpec,
        d: &Spanned<String>,
        p1: Option<[f64; 3]>,
        p2: Option<[f64; 3]>,
        label: &str,
    ) -> Option<Mat3> {
        let kind = f.kind.as_ref().map_or("", |k| k.get_ref().as_str());
        if !matches!(
            kind,
            "table" | "series_spring_damper" | "damper" | "friction"
        ) {
            // (the type's own check reports direction as not applicable where it is not)
            return None;
        }
        if let Some(o) = &f.orientation_deg {
            self.err(
                &o.span(),
                "orientation_deg",
                format!(
                    "{label}: orientation_deg does not apply to an element along the line between its points (direction = \"line\"): its axis is that line"
                ),
            );
            return None;
        }
        if f.point2_m.is_none() {
            self.err(
                &d.span(),
                "point2_m",
                format!(
                    "{label}: missing key 'point2_m': direction = \"line\" acts along the line from point_m to point2_m (expected body 2's attachment point, at least 0.01 m from point_m)"
                ),
            );
            return None;
        }
        let (p1, p2) = (p1?, p2?);
        let v = [p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]];
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if len < 0.01 {
            self.err(
                &f.point2_m.as_ref().map_or(d.span(), |p| p.span()),
                "point2_m",
                format!(
                    "{label}: point2_m lies {len:.4} m from point_m; an element along the line between its points needs them at least 0.01 m apart"
                ),
            );
            return None;
        }
        let x = [v[0] / len, v[1] / len, v[2] / len];
        // y: the vehicle's z × x normalised, or the vehicle's y when the line is vertical
        let h = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let y = if h > 1e-9 {
            [-x[1] / h, x[0] / h, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let z = [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ];
        // columns: the local axes in the vehicle frame
        Some([[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]])
    }

    fn not_applicable(&mut self, f: &ForceSpec, label: &str, kind: &str, allowed: &[&str]) {
        let present: [(&str, Option<Range<usize>>); 18] = [
            ("direction", f.direction.as_ref().map(|v| v.span())),
            (
                "stiffness_n_per_m",
                f.stiffness_n_per_m.as_ref().map(|v| v.span()),
            ),
            (
                "damping_ns_per_m",
                f.damping_ns_per_m.as_ref().map(|v| v.span()),
            ),
            (
                "rotational_stiffness_nm_per_rad",
                f.rotational_stiffness_nm_per_rad.as_ref().map(|v| v.span()),
            ),
            (
                "rotational_damping_nms_per_rad",
                f.rotational_damping_nms_per_rad.as_ref().map(|v| v.span()),
            ),
            ("deflection_mm", f.deflection_mm.as_ref().map(|v| v.span())),
            ("force_n", f.force_n.as_ref().map(|v| v.span())),
            ("symmetric", f.symmetric.as_ref().map(|v| v.span())),
            (
                "velocity_m_per_s",
                f.velocity_m_per_s.as_ref().map(|v| v.span()),
            ),
            (
                "friction_force_n",
                f.friction_force_n.as_ref().map(|v| v.span()),
            ),
            (
                "friction_coefficient",
                f.friction_coefficient.as_ref().map(|v| v.span()),
            ),
            (
                "normal_element",
                f.normal_element.as_ref().map(|v| v.span()),
            ),
            (
                "normal_direction",
                f.normal_direction.as_ref().map(|v| v.span()),
            ),
            ("plane", f.plane.as_ref().map(|v| v.span())),
            ("about", f.about.as_ref().map(|v| v.span())),
            (
                "friction_moment_nm",
                f.friction_moment_nm.as_ref().map(|v| v.span()),
            ),
            (
                "friction_radius_m",
                f.friction_radius_m.as_ref().map(|v| v.span()),
            ),
            ("point2_m", None),
        ];
        for (key, span) in present {
            if let Some(span) = span
                && !allowed.contains(&key)
            {
                self.err(
                    &span,
                    key,
                    format!(
                        "{label}: key '{key}' does not apply to type '{kind}' (it takes: {})",
                        allowed.join(", ")
                    ),
                );
            }
        }
    }

    fn triple(
        &mut self,
        v: &Option<Spanned<NumberOrTriple>>,
        label: &str,
        key: &str,
        unit: &str,
    ) -> Option<[f64; 3]> {
        let Some(v) = v else {
            return Some([0.0; 3]);
        };
        match *v.get_ref() {
            NumberOrTriple::Three(a) if a.iter().all(|x| x.is_finite() && *x >= 0.0) => {
                self.within_bound(&v.span(), &a, label, key).then_some(a)
            }
            NumberOrTriple::Three(a) => {
                self.err(
                    &v.span(),
                    key,
                    format!("{label}: {key} must be non-negative numbers of {unit}, found {a:?}"),
                );
                None
            }
            NumberOrTriple::One(x) => {
                self.err(
                    &v.span(),
                    key,
                    format!(
                        "{label}: {key} of a bushing takes three numbers [x, y, z] in {unit}, found the single number {x}"
                    ),
                );
                None
            }
        }
    }

    fn scalar(
        &mut self,
        v: &Option<Spanned<NumberOrTriple>>,
        table: &Range<usize>,
        label: &str,
        key: &str,
        unit: &str,
        strictly_positive: bool,
    ) -> Option<f64> {
        let v = self.req(v, table, label, key, &format!("one number in {unit}"))?;
        match *v.get_ref() {
            NumberOrTriple::One(x)
                if x.is_finite() && (x > 0.0 || (!strictly_positive && x == 0.0)) =>
            {
                self.within_bound(&v.span(), &[x], label, key).then_some(x)
            }
            NumberOrTriple::One(x) => {
                let want = if strictly_positive {
                    "positive"
                } else {
                    "non-negative"
                };
                self.err(
                    &v.span(),
                    key,
                    format!("{label}: {key} must be a {want} number of {unit}, found {x}"),
                );
                None
            }
            NumberOrTriple::Three(a) => {
                self.err(
                    &v.span(),
                    key,
                    format!("{label}: {key} takes one number in {unit} here, found three {a:?}"),
                );
                None
            }
        }
    }

    fn axis(&mut self, f: &ForceSpec, table: &Range<usize>, label: &str) -> Option<Axis> {
        // along the line between the points: the law's axis is the local x, laid along the line
        // by `Self::force`
        match f.direction.as_ref() {
            Some(d) if d.get_ref() == "line" => Some(Axis::X),
            Some(d) if Axis::from_name(d.get_ref()).is_none() => {
                self.err(
                    &d.span(),
                    "direction",
                    format!(
                        "{label}: direction '{}' is not a local axis (expected \"x\", \"y\", \"z\", or \"line\" for along the line from point_m to point2_m)",
                        d.get_ref()
                    ),
                );
                None
            }
            _ => self.axis_key(&f.direction, "direction", table, label),
        }
    }

    /// The local axis named by the required key `key` (`"x"`, `"y"` or `"z"`).
    fn axis_key(
        &mut self,
        v: &Option<Spanned<String>>,
        key: &str,
        table: &Range<usize>,
        label: &str,
    ) -> Option<Axis> {
        let d = self.req(v, table, label, key, "\"x\", \"y\" or \"z\"")?;
        let axis = Axis::from_name(d.get_ref());
        if axis.is_none() {
            self.err(
                &d.span(),
                key,
                format!(
                    "{label}: {key} '{}' is not a local axis (expected \"x\", \"y\" or \"z\")",
                    d.get_ref()
                ),
            );
        }
        axis
    }

    fn law(
        &mut self,
        kind: &str,
        f: &ForceSpec,
        table: &Range<usize>,
        label: &str,
    ) -> Option<ForceLaw> {
        match kind {
            "bushing" => {
                self.not_applicable(
                    f,
                    label,
                    kind,
                    &[
                        "stiffness_n_per_m",
                        "damping_ns_per_m",
                        "rotational_stiffness_nm_per_rad",
                        "rotational_damping_nms_per_rad",
                    ],
                );
                if f.stiffness_n_per_m.is_none()
                    && f.damping_ns_per_m.is_none()
                    && f.rotational_stiffness_nm_per_rad.is_none()
                    && f.rotational_damping_nms_per_rad.is_none()
                {
                    self.err(
                        table,
                        "stiffness_n_per_m",
                        format!(
                            "{label}: a bushing needs at least one of stiffness_n_per_m, damping_ns_per_m, rotational_stiffness_nm_per_rad, rotational_damping_nms_per_rad"
                        ),
                    );
                }
                let k = self.triple(&f.stiffness_n_per_m, label, "stiffness_n_per_m", "N/m");
                let c = self.triple(&f.damping_ns_per_m, label, "damping_ns_per_m", "N·s/m");
                let kr = self.triple(
                    &f.rotational_stiffness_nm_per_rad,
                    label,
                    "rotational_stiffness_nm_per_rad",
                    "N·m/rad",
                );
                let cr = self.triple(
                    &f.rotational_damping_nms_per_rad,
                    label,
                    "rotational_damping_nms_per_rad",
                    "N·m·s/rad",
                );
                let (k, c, kr, cr) = (k?, c?, kr?, cr?);
                Some(ForceLaw::Bushing {
                    stiffness: [k[0], k[1], k[2], kr[0], kr[1], kr[2]],
                    damping: [c[0], c[1], c[2], cr[0], cr[1], cr[2]],
                })
            }
            "table" => {
                self.not_applicable(
                    f,
                    label,
                    kind,
                    &["direction", "deflection_mm", "force_n", "symmetric"],
                );
                let axis = self.axis(f, table, label);
                let d = self.req(
                    &f.deflection_mm,
                    table,
                    label,
                    "deflection_mm",
                    "an array of increasing deflections in mm",
                );
                let fo = self.req(
                    &f.force_n,
                    table,
                    label,
                    "force_n",
                    "an array of forces in N, one per deflection",
                );
                let symmetric = f.symmetric.as_ref().is_some_and(|s| *s.get_ref());
                let table = match (d, fo) {
                    (Some(d), Some(fo)) => self.force_table(d, fo, symmetric, label),
                    _ => None,
                };
                Some(ForceLaw::Table {
                    axis: axis?,
                    table: table?,
                })
            }
            "series_spring_damper" => {
                self.not_applicable(
                    f,
                    label,
                    kind,
                    &["direction", "stiffness_n_per_m", "damping_ns_per_m"],
                );
                let axis = self.axis(f, table, label);
                let k = self.scalar(
                    &f.stiffness_n_per_m,
                    table,
                    label,
                    "stiffness_n_per_m",
                    "N/m",
                    true,
                );
                let c = self.scalar(
                    &f.damping_ns_per_m,
                    table,
                    label,
                    "damping_ns_per_m",
                    "N·s/m",
                    true,
                );
                if let (Some(k), Some(c), Some(cv)) = (k, c, &f.damping_ns_per_m) {
                    let tau = c / k;
                    if tau < MIN_SERIES_RELAXATION {
                        self.err(
                            &cv.span(),
                            "damping_ns_per_m",
                            format!(
                                "{label}: relaxation time damping_ns_per_m / stiffness_n_per_m = {} N·s/m / {} N/m = {} s is below {} s (an explicit integrator's stable step is about 2τ, so a run would stall); raise damping_ns_per_m to at least {} N·s/m, or, for a mount this stiff, model the damper alone (type = \"bushing\" with damping_ns_per_m)",
                                short_number(c),
                                short_number(k),
                                computed(tau),
                                short_number(MIN_SERIES_RELAXATION),
                                computed(MIN_SERIES_RELAXATION * k)
                            ),
                        );
                        return None;
                    }
                }
                Some(ForceLaw::SeriesSpringDamper {
                    axis: axis?,
                    stiffness: k?,
                    damping: c?,
                })
            }
            "damper" => {
                self.not_applicable(
                    f,
                    label,
                    kind,
                    &[
                        "direction",
                        "velocity_m_per_s",
                        "force_n",
                        "symmetric",
                        "stiffness_n_per_m",
                    ],
                );
                let axis = self.axis(f, table, label);
                let stiffness = match &f.stiffness_n_per_m {
                    None => Some(None),
                    Some(_) => self
                        .scalar(
                            &f.stiffness_n_per_m,
                            table,
                            label,
                            "stiffness_n_per_m",
                            "N/m",
                            true,
                        )
                        .map(Some),
                };
                let v = self.req(
                    &f.velocity_m_per_s,
                    table,
                    label,
                    "velocity_m_per_s",
                    "an array of increasing velocities in m/s",
                );
                let fo = self.req(
                    &f.force_n,
                    table,
                    label,
                    "force_n",
                    "an array of damper forces in N, one per velocity",
                );
                let symmetric = f.symmetric.as_ref().is_some_and(|s| *s.get_ref());
                let t = match (v, fo) {
                    (Some(v), Some(fo)) => self.damper_table(v, fo, symmetric, label),
                    _ => None,
                };
                if let (Some(Some(k)), Some(t), Some(kv)) = (stiffness, &t, &f.stiffness_n_per_m)
                    && !self.damper_relaxation(t, k, &kv.span(), label)
                {
                    return None;
                }
                Some(ForceLaw::Damper {
                    axis: axis?,
                    table: t?,
                    stiffness: stiffness?,
                })
            }
            "friction" => self.friction(f, table, label, false),
            "rotational_friction" => self.friction(f, table, label, true),
            "planar_friction" => self.planar_friction(f, table, label),
            _ => {
                self.not_applicable(f, label, kind, &["rotational_stiffness_nm_per_rad"]);
                let k = self.scalar(
                    &f.rotational_stiffness_nm_per_rad,
                    table,
                    label,
                    "rotational_stiffness_nm_per_rad",
                    "N·m/rad",
                    false,
                )?;
                Some(ForceLaw::AntiRollBar { stiffness: k })
            }
        }
    }

    /// A non-negative number of `unit` (absent: 0).
    fn non_negative(
        &mut self,
        v: &Option<Spanned<f64>>,
        label: &str,
        key: &str,
        unit: &str,
    ) -> Option<f64> {
        let Some(v) = v else {
            return Some(0.0);
        };
        let x = *v.get_ref();
        if x.is_finite() && x >= 0.0 {
            Some(x)
        } else {
            let of = if unit.is_empty() {
                String::new()
            } else {
                format!(" of {unit}")
            };
            self.err(
                &v.span(),
                key,
                format!("{label}: {key} must be a non-negative number{of}, found {x}"),
            );
            None
        }
    }

    /// A friction element, along its `direction` or, `rotational`, about the axis `about`; its
    /// `normal_element` is resolved once every element is compiled ([`Self::resolve_normals`]).
    fn friction(
        &mut self,
        f: &ForceSpec,
        table: &Range<usize>,
        label: &str,
        rotational: bool,
    ) -> Option<ForceLaw> {
        let (kind, axis_key, stiffness_key, stiffness_value, unit) = if rotational {
            (
                "rotational_friction",
                "about",
                "rotational_stiffness_nm_per_rad",
                &f.rotational_stiffness_nm_per_rad,
                "N·m/rad (the stick stiffness)",
            )
        } else {
            (
                "friction",
                "direction",
                "stiffness_n_per_m",
                &f.stiffness_n_per_m,
                "N/m (the stick stiffness)",
            )
        };
        let mut keys = vec![axis_key, stiffness_key];
        keys.extend(friction_limit_keys(rotational));
        self.not_applicable(f, label, kind, &keys);
        let axis = if rotational {
            self.axis_key(&f.about, "about", table, label)
        } else {
            self.axis(f, table, label)
        };
        let k = self.scalar(stiffness_value, table, label, stiffness_key, unit, true);
        let limit = self.friction_limit(f, table, label, kind, rotational);
        let (force, coefficient) = limit?;
        Some(ForceLaw::Friction {
            axis: axis?,
            rotational,
            stiffness: k?,
            force,
            coefficient,
            normal: None,
        })
    }

    /// The sliding limit of a friction element of type `kind`: its constant part
    /// (`friction_force_n`, or `friction_moment_nm` when `rotational`) and the coefficient on the
    /// normal element's force (times `friction_radius_m` when rotational), checked together.
    fn friction_limit(
        &mut self,
        f: &ForceSpec,
        table: &Range<usize>,
        label: &str,
        kind: &str,
        rotational: bool,
    ) -> Option<(f64, f64)> {
        let (constant_key, constant, unit) = if rotational {
            ("friction_moment_nm", &f.friction_moment_nm, "N·m")
        } else {
            ("friction_force_n", &f.friction_force_n, "N")
        };
        let force = self.non_negative(constant, label, constant_key, unit);
        let mu = self.non_negative(&f.friction_coefficient, label, "friction_coefficient", "");
        match (&f.friction_coefficient, &f.normal_element) {
            (Some(c), None) => self.err(
                &c.span(),
                "friction_coefficient",
                format!(
                    "{label}: friction_coefficient needs normal_element, the force element whose force presses the surfaces together"
                ),
            ),
            (None, Some(n)) => self.err(
                &n.span(),
                "normal_element",
                format!("{label}: normal_element needs friction_coefficient (expected a number >= 0)"),
            ),
            (None, None) if constant.is_none() => self.err(
                table,
                constant_key,
                format!(
                    "{label}: a {kind} element needs {constant_key} ({unit}), or friction_coefficient with normal_element, or both"
                ),
            ),
            _ => {}
        }
        if let (Some(d), None) = (&f.normal_direction, &f.normal_element) {
            self.err(
                &d.span(),
                "normal_direction",
                format!("{label}: normal_direction needs normal_element, the force element whose force presses the surfaces together"),
            );
        }
        // the lever of the normal load's friction about the axis
        let radius = match (rotational, &f.friction_radius_m) {
            (false, _) => Some(1.0),
            (true, Some(r)) => self.positive(r, label, "friction_radius_m", "m"),
            (true, None) if f.friction_coefficient.is_some() => {
                self.err(
                    table,
                    "friction_radius_m",
                    format!(
                        "{label}: missing key 'friction_radius_m' (expected the radius in m at which the normal force rubs: the sliding moment is friction_coefficient × normal force × radius)"
                    ),
                );
                None
            }
            (true, None) => Some(0.0),
        };
        Some((force?, mu? * radius?))
    }

    /// A planar friction element: a friction element (of force) in the `plane` of two local
    /// axes, one stick stiffness and one sliding force for every direction.
    fn planar_friction(
        &mut self,
        f: &ForceSpec,
        table: &Range<usize>,
        label: &str,
    ) -> Option<ForceLaw> {
        let mut keys = vec!["plane", "stiffness_n_per_m"];
        keys.extend(friction_limit_keys(false));
        self.not_applicable(f, label, "planar_friction", &keys);
        let plane = self.req(
            &f.plane,
            table,
            label,
            "plane",
            "two different local axes, e.g. \"xy\"",
        );
        let axes = plane.and_then(|p| {
            let text = p.get_ref().as_str();
            let axis = |c: char| Axis::from_name(c.encode_utf8(&mut [0u8; 4]));
            let mut chars = text.chars();
            match (
                chars.next().and_then(axis),
                chars.next().and_then(axis),
                chars.next(),
            ) {
                (Some(a), Some(b), None) if a != b => Some([a, b]),
                _ => {
                    self.err(
                        &p.span(),
                        "plane",
                        format!(
                            "{label}: plane '{text}' is not two different local axes (expected \"xy\", \"yz\", \"xz\" or one of them reversed)"
                        ),
                    );
                    None
                }
            }
        });
        let k = self.scalar(
            &f.stiffness_n_per_m,
            table,
            label,
            "stiffness_n_per_m",
            "N/m (the stick stiffness)",
            true,
        );
        let limit = self.friction_limit(f, table, label, "planar_friction", false);
        let (force, coefficient) = limit?;
        Some(ForceLaw::PlanarFriction {
            axes: axes?,
            stiffness: k?,
            force,
            coefficient,
            normal: None,
        })
    }

    /// The rule by which the force of normal element `target` (compiled with `law`) gives the
    /// normal load of friction element `fs`: its key `normal_direction`, a signed local axis of
    /// the normal element (`"z"`, `"-z"`, …) or `"any"`. `at` is the span of its
    /// `normal_element`.
    fn normal_rule(
        &mut self,
        fs: &ForceSpec,
        at: &Range<usize>,
        label: &str,
        target: &str,
        law: &ForceLaw,
    ) -> Option<NormalRule> {
        if matches!(law, ForceLaw::AntiRollBar { .. }) {
            self.err(
                at,
                "normal_element",
                format!(
                    "{label}: normal_element '{target}' is an anti-roll bar, which carries a moment and no force; expected a spring, table, damper or bushing element"
                ),
            );
            return None;
        }
        let Some(dir) = &fs.normal_direction else {
            self.err(
                at,
                "normal_direction",
                format!(
                    "{label}: missing key 'normal_direction' (expected the local axis of '{target}' along which its force on its body2 presses the rubbing surfaces, with its sign: \"x\", \"y\", \"z\", \"-x\", \"-y\" or \"-z\"; the load is zero when that force turns the other way; or \"any\" for the magnitude of its whole force)"
                ),
            );
            return None;
        };
        let text = dir.get_ref().trim();
        let (sign, name) = match text.strip_prefix('-') {
            Some(rest) => (Sign::Minus, rest),
            None => (Sign::Plus, text.strip_prefix('+').unwrap_or(text)),
        };
        let axis = match (Axis::from_name(name), name) {
            (Some(a), _) => a,
            (None, "any") if sign == Sign::Plus => return Some(NormalRule::Magnitude),
            _ => {
                self.err(
                    &dir.span(),
                    "normal_direction",
                    format!(
                        "{label}: normal_direction '{text}' is not a signed local axis (expected \"x\", \"y\", \"z\", \"-x\", \"-y\", \"-z\" or \"any\")"
                    ),
                );
                return None;
            }
        };
        // a one-axis element has force along its own axis only
        let own = match law {
            ForceLaw::Table { axis, .. }
            | ForceLaw::SeriesSpringDamper { axis, .. }
            | ForceLaw::Damper { axis, .. } => Some(*axis),
            _ => None,
        };
        if let Some(own) = own
            && own != axis
        {
            self.err(
                &dir.span(),
                "normal_direction",
                format!(
                    "{label}: normal_direction '{text}': '{target}' acts along its local {} only (expected \"{0}\" or \"-{0}\")",
                    own.name()
                ),
            );
            return None;
        }
        Some(NormalRule::Along { axis, sign })
    }

    /// Resolve each friction element's `normal_element` to the element it names, which must
    /// be declared, differ from it and not be a friction element itself (checked also when the
    /// friction element failed its own checks).
    fn resolve_normals(&mut self, spec: &VehicleSpec, forces: &mut [ForceElement]) {
        let declared = |n: &str| {
            spec.force.iter().any(|o| {
                o.get_ref()
                    .name
                    .as_ref()
                    .is_some_and(|m| m.get_ref().trim() == n)
            })
        };
        for fs in &spec.force {
            let fs = fs.get_ref();
            let (Some(normal), Some(kind)) = (&fs.normal_element, &fs.kind) else {
                continue;
            };
            if !matches!(
                kind.get_ref().as_str(),
                "friction" | "planar_friction" | "rotational_friction"
            ) {
                continue;
            }
            let name = fs.name.as_ref().map_or("", |n| n.get_ref().trim());
            let label = format!("force '{name}'");
            let target = normal.get_ref().trim();
            let problem = if !declared(target) {
                format!(
                    "{label}: normal_element refers to unknown force element '{target}'{}",
                    did_you_mean(
                        target,
                        spec.force.iter().filter_map(|o| o
                            .get_ref()
                            .name
                            .as_ref()
                            .map(|n| n.get_ref().trim()))
                    )
                )
            } else if target == name {
                format!(
                    "{label}: normal_element names the element itself; expected another force element"
                )
            } else if spec.force.iter().any(|o| {
                let o = o.get_ref();
                o.name
                    .as_ref()
                    .is_some_and(|n| n.get_ref().trim() == target)
                    && o.kind.as_ref().is_some_and(|k| {
                        matches!(
                            k.get_ref().as_str(),
                            "friction" | "planar_friction" | "rotational_friction"
                        )
                    })
            }) {
                format!(
                    "{label}: normal_element '{target}' is a friction element; expected a spring, table or damper element whose force is the normal load"
                )
            } else {
                // declared and not a friction element: bind it when both compiled (otherwise
                // their own problems are reported)
                let j = forces.iter().position(|e| e.name == target);
                let Some(j) = j else { continue };
                let rule = self.normal_rule(fs, &normal.span(), &label, target, &forces[j].law);
                let Some(rule) = rule else {
                    continue;
                };
                if let Some(i) = forces.iter().position(|e| e.name == name)
                    && let ForceLaw::Friction { normal, .. }
                    | ForceLaw::PlanarFriction { normal, .. } = &mut forces[i].law
                {
                    *normal = Some(NormalLoad {
                        element: ForceElementId(j),
                        rule,
                    });
                }
                continue;
            };
            self.err(&normal.span(), "normal_element", problem);
        }
    }

    /// The points of a piecewise-linear table: at least two, one value per abscissa, finite,
    /// the abscissae strictly increasing (and the values too when `increasing_values` gives
    /// the reason), starting at 0 or above for a `symmetric` (mirrored) table. File units.
    fn table_points(
        &mut self,
        x: (&Spanned<Vec<Spanned<f64>>>, &str, &str),
        y: (&Spanned<Vec<Spanned<f64>>>, &str, &str),
        symmetric: bool,
        increasing_values: Option<&str>,
        label: &str,
    ) -> Option<(Vec<f64>, Vec<f64>)> {
        let ((xs, x_key, x_noun), (ys, y_key, y_noun)) = (x, y);
        let mut ok = true;
        let (xv, yv) = (xs.get_ref(), ys.get_ref());
        if xv.len() < 2 {
            self.err(
                &xs.span(),
                x_key,
                format!(
                    "{label}: {x_key} needs at least 2 points, found {}",
                    xv.len()
                ),
            );
            ok = false;
        }
        if xv.len() != yv.len() {
            self.err(
                &ys.span(),
                y_key,
                format!(
                    "{label}: {y_key} has {} values but {x_key} has {}; expected one {y_noun} per {x_noun}",
                    yv.len(),
                    xv.len()
                ),
            );
            ok = false;
        }
        let lists = [(x_key, xv, Some("")), (y_key, yv, increasing_values)];
        for (key, list, increasing) in lists {
            for v in list {
                if !v.get_ref().is_finite() {
                    self.err(
                        &v.span(),
                        key,
                        format!(
                            "{label}: {key} values must be finite, found {}",
                            v.get_ref()
                        ),
                    );
                    ok = false;
                }
            }
            let Some(why) = increasing else {
                continue;
            };
            for w in list.windows(2) {
                if *w[1].get_ref() <= *w[0].get_ref() {
                    self.err(
                        &w[1].span(),
                        key,
                        format!(
                            "{label}: {key} must be strictly increasing{why}, but {} follows {}",
                            w[1].get_ref(),
                            w[0].get_ref()
                        ),
                    );
                    ok = false;
                }
            }
        }
        if symmetric
            && let Some(first) = xv.first()
            && *first.get_ref() < 0.0
        {
            self.err(
                &first.span(),
                x_key,
                format!(
                    "{label}: a symmetric table is given for {x_noun}s >= 0, but {x_key} starts at {}",
                    first.get_ref()
                ),
            );
            ok = false;
        }
        // mirrored as an odd law, −F(−x): a value at 0 would be a step through zero
        if symmetric
            && let (Some(x0), Some(y0)) = (xv.first(), yv.first())
            && *x0.get_ref() == 0.0
            && *y0.get_ref() != 0.0
        {
            self.err(
                &y0.span(),
                y_key,
                format!(
                    "{label}: a symmetric table is mirrored as an odd law (−{y_noun}(−{x_noun})), so its {y_key} at {x_key} = 0 must be 0, found {} (a step through zero)",
                    short_number(*y0.get_ref())
                ),
            );
            ok = false;
        }
        ok.then(|| {
            (
                xv.iter().map(|v| *v.get_ref()).collect(),
                yv.iter().map(|v| *v.get_ref()).collect(),
            )
        })
    }

    /// Whether every value of the table key `key` lies within ±`max` (file units, `unit`);
    /// reports the first one outside.
    fn table_range(
        &mut self,
        list: &Spanned<Vec<Spanned<f64>>>,
        key: &str,
        max: f64,
        unit: &str,
        label: &str,
    ) -> bool {
        let Some(v) = list.get_ref().iter().find(|v| v.get_ref().abs() > max) else {
            return true;
        };
        self.err(
            &v.span(),
            key,
            format!(
                "{label}: {key} value {} {unit} is implausible (expected within ±{} {unit})",
                short_number(*v.get_ref()),
                short_number(max)
            ),
        );
        false
    }

    /// Whether the slope of every segment of a table is finite and at most `max` in magnitude
    /// (SI); reports the first segment above it, at the value that ends it.
    fn table_slopes(&mut self, t: &TableSlopes<'_>, label: &str) -> bool {
        for i in 1..t.x.len() {
            let dx = (t.x[i] - t.x[i - 1]) * t.x_scale;
            let dy = t.y[i] - t.y[i - 1];
            // abscissae too close to be told apart in SI make the slope infinite
            let slope = if dx > 0.0 { dy / dx } else { f64::INFINITY };
            if slope.abs() <= t.max {
                continue;
            }
            self.err(
                &t.spans[i],
                "force_n",
                format!(
                    "{label}: force_n: the slope between {} and {} {} ({}) is {} {}, implausibly steep (expected at most {} {}; check the units of {} and force_n)",
                    short_number(t.x[i - 1]),
                    short_number(t.x[i]),
                    t.x_unit,
                    t.x_key,
                    computed(slope.abs()),
                    t.slope_unit,
                    short_number(t.max),
                    t.slope_unit,
                    t.x_key
                ),
            );
            return false;
        }
        true
    }

    /// Whether a damper table in series with the mount stiffness `k` \[N/m\] relaxes no faster
    /// than [`MIN_SERIES_RELAXATION`]: τ = (the table's smallest slope) / k; reports it at
    /// `span`, the mount stiffness's value.
    fn damper_relaxation(
        &mut self,
        t: &DamperTable,
        k: f64,
        span: &Range<usize>,
        label: &str,
    ) -> bool {
        let Some((i, slope)) = t
            .velocity
            .windows(2)
            .zip(t.force.windows(2))
            .map(|(v, f)| (f[1] - f[0]) / (v[1] - v[0]))
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
        else {
            return true;
        };
        let tau = slope / k;
        if tau >= MIN_SERIES_RELAXATION {
            return true;
        }
        self.err(
            span,
            "stiffness_n_per_m",
            format!(
                "{label}: relaxation time (slope of velocity_m_per_s/force_n) / stiffness_n_per_m = {} N·s/m / {} N/m = {} s (between {} and {} m/s) is below {} s (an explicit integrator's stable step is about 2τ, so a run would stall); a mount this stiff is better modelled by the damper alone (drop stiffness_n_per_m), or lower stiffness_n_per_m to at most {} N/m, or raise the table's damping",
                computed(slope),
                short_number(k),
                computed(tau),
                short_number(t.velocity[i]),
                short_number(t.velocity[i + 1]),
                short_number(MIN_SERIES_RELAXATION),
                computed(slope / MIN_SERIES_RELAXATION)
            ),
        );
        false
    }

    fn damper_table(
        &mut self,
        v: &Spanned<Vec<Spanned<f64>>>,
        f: &Spanned<Vec<Spanned<f64>>>,
        symmetric: bool,
        label: &str,
    ) -> Option<DamperTable> {
        let (mut velocity, mut force) = self.table_points(
            (v, "velocity_m_per_s", "velocity"),
            (f, "force_n", "force"),
            symmetric,
            Some(" (a damper's force grows with its velocity and must be invertible)"),
            label,
        )?;
        let in_range = self.table_range(v, "velocity_m_per_s", MAX_TABLE_VELOCITY, "m/s", label)
            & self.table_range(f, "force_n", MAX_TABLE_FORCE, "N", label);
        if !in_range {
            return None;
        }
        let mut spans: Vec<Range<usize>> = f.get_ref().iter().map(|x| x.span()).collect();
        if symmetric && velocity[0] > 0.0 {
            spans.insert(0, spans[0].clone());
            if force[0] <= 0.0 {
                self.err(
                    &f.span(),
                    "force_n",
                    format!(
                        "{label}: the mirrored table passes through 0 N at rest, so its first force must be positive, found {}",
                        force[0]
                    ),
                );
                return None;
            }
            velocity.insert(0, 0.0);
            force.insert(0, 0.0);
        }
        let slopes = TableSlopes {
            x: &velocity,
            x_scale: 1.0,
            y: &force,
            spans: &spans,
            x_key: "velocity_m_per_s",
            x_unit: "m/s",
            max: MAX_DAMPING,
            slope_unit: "N·s/m",
        };
        if !self.table_slopes(&slopes, label) {
            return None;
        }
        let t = DamperTable {
            velocity,
            force,
            symmetric,
        };
        let scale = t.force.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let at_rest = t.force(0.0);
        if at_rest.abs() > 1e-9 * scale {
            self.err(
                &f.span(),
                "force_n",
                format!(
                    "{label}: the table gives {} N at zero velocity; a damper carries no force at rest (expected 0)",
                    short_number(at_rest)
                ),
            );
            return None;
        }
        Some(t)
    }

    fn force_table(
        &mut self,
        d: &Spanned<Vec<Spanned<f64>>>,
        f: &Spanned<Vec<Spanned<f64>>>,
        symmetric: bool,
        label: &str,
    ) -> Option<ForceTable> {
        let (mut d_mm, mut force) = self.table_points(
            (d, "deflection_mm", "deflection"),
            (f, "force_n", "force"),
            symmetric,
            None,
            label,
        )?;
        let in_range =
            self.table_range(d, "deflection_mm", MAX_TABLE_DEFLECTION * 1e3, "mm", label)
                & self.table_range(f, "force_n", MAX_TABLE_FORCE, "N", label);
        if !in_range {
            return None;
        }
        let mut spans: Vec<Range<usize>> = f.get_ref().iter().map(|x| x.span()).collect();
        if symmetric && d_mm[0] > 0.0 {
            // Pin the mirrored law through the origin so that F(0) = 0 and it stays odd.
            d_mm.insert(0, 0.0);
            force.insert(0, 0.0);
            spans.insert(0, spans[0].clone());
        }
        let slopes = TableSlopes {
            x: &d_mm,
            x_scale: 1e-3,
            y: &force,
            spans: &spans,
            x_key: "deflection_mm",
            x_unit: "mm",
            max: MAX_STIFFNESS,
            slope_unit: "N/m",
        };
        if !self.table_slopes(&slopes, label) {
            return None;
        }
        let deflection: Vec<f64> = d_mm.iter().map(|x| x * 1e-3).collect();
        let table = ForceTable {
            deflection,
            force,
            symmetric,
        };
        // The table gives the force beyond the static preload, from the nominal (loaded)
        // geometry (docs/formats/vehicle.md): a force at zero deflection would push the vehicle
        // off that geometry at rest. (A symmetric table is pinned through 0 above.)
        let f0 = table.force(0.0);
        let scale = table.force.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !symmetric && f0.abs() > 1e-9 * scale {
            self.err(
                &f.span(),
                "force_n",
                format!(
                    "{label}: the table's force at deflection_mm = 0 (the vehicle file's loaded geometry) is {} N{}, expected 0: a table gives the force beyond the static load the element carries there (computed by the simulator); shift force_n so that it passes through 0 N at 0 mm",
                    short_number(f0),
                    if d_mm[0] > 0.0 || d_mm[d_mm.len() - 1] < 0.0 {
                        " (extrapolated from its end)"
                    } else {
                        ""
                    }
                ),
            );
            return None;
        }
        Some(table)
    }
}
