//! The equations of motion: one right-hand-side evaluation with its stages in order.
//!
//! 1. **motion**: distance run s(t), speed V and its rate from the scene's speed profile;
//! 2. **frames**: each member has its own track-following frame at s + x₀ (x₀ its nominal x),
//!    from the track geometry: origin, orientation, angular velocity V·k and acceleration;
//! 3. **kinematics**: each member's centre of gravity, orientation and velocities from its
//!    coordinates relative to its frame;
//! 4. **force elements**: deflections between attachment points (in body 1's axes), laws,
//!    forces and moments on both members, internal-state rates;
//! 5. **contact**: each wheel calls the contact crate online with its pose and velocities
//!    relative to its rail (irregularities move the rails), the wheels in parallel (each in its
//!    own contact workspace), then the forces back to the wheelsets in the wheels' order;
//! 6. **equations of motion** in each member's frame, with the frame's inertial terms.
//!
//! The derivation and its approximations are in `docs/models/dynamics.md`.

use std::time::Instant;

use railsim_contact::{
    ContactError, ContactWorkspace, PatchResult, Side, WarmStart, WheelRailContact, WheelsetPose,
    WheelsetVelocity,
};
use railsim_ode::{OdeSystem, RhsError};
use railsim_track::TrackFrame;
use railsim_vehicle::model::{Axis, ForceLaw, series_force, series_state_rate};
use railsim_vehicle::suspension::{damper_series_law, friction_law, planar_friction_law};
use rayon::prelude::*;

use crate::math::{
    M3, V3, add, cross, dot, mat_mul, mat_t_mul, mul, mul_t, rot_x, rot_y, rot_z, rotation_rpy,
    scale, small_rotation, sub,
};
use crate::model::{ElementModel, End, MemberIx, MemberKind, SimModel};

/// \[m\] the distance below which the points of an element along its line stop a run: its
/// direction, the line's, is lost where they meet (they start at least 0.01 m apart,
/// `railsim_vehicle::ForceElement::line`).
pub const LINE_COLLAPSE: f64 = 1e-3;

/// A member's frame and kinematics at one evaluation (global components unless noted).
#[derive(Debug, Clone, Copy, Default)]
pub struct MemberKin {
    /// Orientation of the member's track frame (columns: its axes).
    pub frame: M3,
    /// \[m\] origin of the track frame (centre line, plane of the rail tops).
    pub origin: V3,
    /// \[1/m\] Darboux vector of the track at the frame: its angular velocity per metre run.
    pub darboux: V3,
    /// \[rad/s\] angular velocity of the frame.
    pub omega_frame: V3,
    /// \[rad/s²\] its angular acceleration.
    pub alpha_frame: V3,
    /// \[m/s²\] acceleration of the frame origin.
    pub accel_origin: V3,
    /// \[m/s\] velocity of the frame origin.
    pub vel_origin: V3,
    /// \[m, m, m, rad, rad, rad\] coordinates relative to the frame (pitch 0 for wheelsets).
    pub q: [f64; 6],
    /// Their rates (a wheelset's spin rate at index 4).
    pub qd: [f64; 6],
    /// \[m\] centre of gravity relative to the frame origin, frame components (x is always 0:
    /// the frame follows the member along the track).
    pub r_local: V3,
    /// \[m\] centre of gravity.
    pub cog: V3,
    /// \[m/s\] its velocity.
    pub vel: V3,
    /// Orientation of the body (a wheelset's non-spinning axle frame).
    pub orient: M3,
    /// \[rad/s\] angular velocity (a wheelset's without its spin).
    pub omega: V3,
    /// \[N\] sum of the forces on the member.
    pub force: V3,
    /// \[N m\] sum of the moments about its centre of gravity.
    pub moment: V3,
    /// \[m/s²\] acceleration of the centre of gravity, from stage 7 of a recording evaluation
    /// (zero otherwise): that of the frame's point plus the relative acceleration of the free
    /// coordinates (a frozen one moves with its frame, whatever force its constraint takes).
    pub accel: V3,
    /// \[rad/s²\] angular acceleration of a body, likewise (zero for wheelsets).
    pub alpha: V3,
}

/// One patch as the simulation saw it, for logs and summaries.
#[derive(Debug, Clone, Copy)]
pub struct PatchRecord {
    /// Index into [`SimModel::wheels`].
    pub wheel: usize,
    /// The contact crate's result (in the rail's frame when the track has irregularities), its
    /// point moved ahead by an out-of-round wheel's support lead (`SimModel::wheel_support`),
    /// where its forces act.
    pub result: PatchResult,
    /// \[N\] force on the wheel in the wheelset's track frame (its share: times `weight`).
    pub force_frame: V3,
    /// \[-\] the share of the patch's forces the wheel carries: 1, but in a rail transition
    /// (`TrackModel::rail_blend_at`) its rails' weight; `result` holds the whole forces.
    pub weight: f64,
}

/// Time spent per stage, accumulated over evaluations.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CostSplit {
    /// \[s\] contact evaluations.
    pub contact: f64,
    /// \[s\] force elements (suspension).
    pub suspension: f64,
    /// \[s\] everything in the right-hand side (frames, kinematics, equations of motion too).
    pub rhs: f64,
    /// Right-hand-side evaluations.
    pub evaluations: u64,
}

/// One force element at the last recorded evaluation (`Workspace::record`), local axes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ElementRecord {
    /// \[m\] deflection: body 2's attachment point relative to body 1's, from nominal
    pub deflection: V3,
    /// \[m/s\] its rate
    pub rate: V3,
    /// \[rad\] rotation of body 2 relative to body 1 (small angles)
    pub rotation: V3,
    /// \[N\] force on body 2
    pub force: V3,
    /// \[N·m\] moment on body 2
    pub moment: V3,
    /// \[m, or rad for a rotational friction\] the internal states: the first `states` of
    /// the array
    pub state: [f64; 2],
    /// How many internal states the element has (0, 1 or 2)
    pub states: usize,
    /// \[N\] a friction element's sliding force
    pub sliding_force: Option<f64>,
    /// \[N·m\] a rotational friction element's sliding moment
    pub sliding_moment: Option<f64>,
    /// \[W\] power the element absorbs from the bodies, −(F·Δ̇ + M·ω) with F, M its force and
    /// moment on body 2 and Δ̇, ω body 2's velocity and angular velocity relative to body 1 at
    /// the attachment (local axes): the rate of its stored energy plus what it dissipates
    pub power: f64,
    /// \[W\] the part of `power` the element dissipates (never negative; 0 for springs, tables
    /// and anti-roll bars; see the function `dissipation` of this module)
    pub dissipation: f64,
}

/// \[W\] the power a force element with law `law` dissipates: its force `f` and moment `mo` on
/// body 2, the relative rates `lin_rate`, `rot_rate` (local axes) and, for an element with
/// internal states, their rates `state_rate` (from its first state on). A bushing's dampers
/// dissipate Σ c v²; an element whose internal state is a damper's elongation or a friction
/// slider's position dissipates the force it carries times the state's rate, −F·ṡ (the rest
/// of −F·Δ̇ is the rate of the energy its spring stores, ½ k (Δ − s)²); a damper without a
/// series stiffness −F·Δ̇.
fn dissipation(
    law: &ForceLaw,
    state_rate: Option<&[f64]>,
    f: V3,
    mo: V3,
    lin_rate: V3,
    rot_rate: V3,
) -> f64 {
    let rate = |k: usize| state_rate.map_or(0.0, |r| r[k]);
    match law {
        ForceLaw::Bushing { damping, .. } => (0..3)
            .map(|k| damping[k] * lin_rate[k].powi(2) + damping[3 + k] * rot_rate[k].powi(2))
            .sum(),
        ForceLaw::Table { .. } | ForceLaw::AntiRollBar { .. } => 0.0,
        ForceLaw::Damper {
            axis,
            stiffness: None,
            ..
        } => -f[axis.index()] * lin_rate[axis.index()],
        ForceLaw::SeriesSpringDamper { axis, .. }
        | ForceLaw::Damper { axis, .. }
        | ForceLaw::Friction {
            axis,
            rotational: false,
            ..
        } => -f[axis.index()] * rate(0),
        ForceLaw::Friction { axis, .. } => -mo[axis.index()] * rate(0),
        ForceLaw::PlanarFriction { axes, .. } => {
            -(f[axes[0].index()] * rate(0) + f[axes[1].index()] * rate(1))
        }
    }
}

/// Reusable buffers of the right-hand side: nothing is allocated per evaluation once they have
/// grown.
pub struct Workspace {
    /// Per member.
    pub kin: Vec<MemberKin>,
    /// \[m\] track position of the vehicle reference at the current evaluation.
    pub track_position: f64,
    /// \[m/s\] speed at the current evaluation.
    pub speed: f64,
    /// A contact workspace for the evaluations outside the right-hand side (the static
    /// solution).
    pub contact: ContactWorkspace,
    /// Per wheel: the pose, velocities and rail frame of the current evaluation.
    wheel_input: Vec<WheelInput>,
    /// Per wheel: the buffers of its contact evaluations (the wheels are evaluated in parallel).
    wheel_contact: Vec<WheelContact>,
    /// Patches of the last evaluation, filled only when `record` is set.
    pub patches: Vec<PatchRecord>,
    /// \[N\] per wheel: force on the wheel in its wheelset's track frame, summed over patches.
    pub wheel_force: Vec<V3>,
    /// Keep the patches of each evaluation in `patches` (for outputs).
    pub record: bool,
    /// Measure the cost of the stages.
    pub timing: bool,
    /// Accumulated cost.
    pub cost: CostSplit,
    /// \[m or rad\] deflection (rotation for a rotational friction; two components for a
    /// planar friction) of each element with an internal state (series spring-damper, damper
    /// with a series stiffness, friction; 0 for other elements): the states' values at which the
    /// element is relaxed.
    pub series_delta: Vec<[f64; 2]>,
    /// \[N\] per element: its force on its second end in its local axes, preload included
    /// (the normal load of friction elements, `railsim_vehicle::NormalLoad`).
    pub element_force: Vec<[f64; 3]>,
    /// Per element: deflections and forces, filled only when `record` is set (for outputs).
    pub elements: Vec<ElementRecord>,
    /// The wheel and the message of the last failed contact evaluation (for the stop error).
    pub failure: Option<(String, String)>,
}

impl Workspace {
    /// Buffers for `model`.
    pub fn new(model: &SimModel) -> Workspace {
        Workspace {
            kin: vec![MemberKin::default(); model.members.len()],
            track_position: model.start,
            speed: 0.0,
            contact: ContactWorkspace::new(),
            wheel_input: vec![WheelInput::default(); model.wheels.len()],
            wheel_contact: (0..model.wheels.len())
                .map(|_| WheelContact::default())
                .collect(),
            patches: Vec::with_capacity(4 * model.wheels.len()),
            wheel_force: vec![[0.0; 3]; model.wheels.len()],
            record: false,
            timing: false,
            cost: CostSplit::default(),
            series_delta: vec![[0.0; 2]; model.elements.len()],
            element_force: vec![[0.0; 3]; model.elements.len()],
            elements: vec![ElementRecord::default(); model.elements.len()],
            failure: None,
        }
    }

    /// Per wheel, the warm start of its contact search on the rails under it (its counts of
    /// warm and cold searches).
    pub fn warm_starts(&self) -> impl Iterator<Item = &WarmStart> {
        self.wheel_contact.iter().map(|w| &w.main.warm)
    }

    /// Make every wheel's next contact searches cold (the rails before and in a transition).
    /// Also forgets the evaluations kept for reuse, so that a run does not depend on the
    /// evaluations before it.
    pub fn invalidate_warm_starts(&mut self) {
        for w in &mut self.wheel_contact {
            w.main.invalidate();
            w.partner.invalidate();
        }
    }
}

/// One wheel's contact evaluation input: its wheelset's pose and velocities relative to the
/// rail, the rail's frame, and the axle centre relative to the wheelset's track frame.
#[derive(Debug, Clone, Copy, Default)]
struct WheelInput {
    pose: WheelsetPose,
    vel: WheelsetVelocity,
    rail: RailFrame,
    r: V3,
    /// the track's rail section under the wheel (`WheelModel::contacts`)
    section: usize,
    /// its weight: below 1 in its transition, where section − 1 carries the rest (`WheelContact::partner`)
    weight: f64,
    /// \[m\] an out-of-round wheel's support point ahead of the axle (`SimModel::wheel_support`)
    lead: f64,
}

/// The buffers of one contact evaluation: its workspace (whose `patches` hold the patches of
/// the last evaluation), its warm start (used when the model asks for it) and the error of its
/// last evaluation, if it failed; and the inputs and patches of its last two successful
/// evaluations, which an evaluation of the same input reuses (`ContactSlot::evaluate`).
#[derive(Default)]
struct ContactSlot {
    contact: ContactWorkspace,
    warm: WarmStart,
    error: Option<ContactError>,
    /// the input whose patches `contact.patches` holds
    key: Option<EvalKey>,
    /// the evaluation before it: its input and its patches
    saved_key: Option<EvalKey>,
    saved: Vec<PatchResult>,
}

/// What a contact evaluation depends on: the rail section (which pair) and the wheelset's pose
/// and velocities relative to its rail.
#[derive(Debug, Clone, Copy, PartialEq)]
struct EvalKey {
    section: usize,
    pose: WheelsetPose,
    vel: WheelsetVelocity,
}

impl ContactSlot {
    /// Evaluates `key` with `contact` (warm-started if `warm`), or reuses the patches of the
    /// last or the one before, if either had the same input exactly. A difference Jacobian by
    /// column groups (railsim_ode) moves a few wheelsets and rails per group and returns to the
    /// base state between groups, so the other wheels' inputs repeat: the base's patches are
    /// kept beside the perturbed ones. The result is then that of the earlier evaluation of the
    /// same input (with the warm start, as found from that evaluation's starting point).
    fn evaluate(&mut self, contact: &WheelRailContact, side: Side, key: EvalKey, warm: bool) {
        if self.key == Some(key) {
            self.error = None;
            return;
        }
        if self.saved_key == Some(key) {
            std::mem::swap(&mut self.contact.patches, &mut self.saved);
            std::mem::swap(&mut self.key, &mut self.saved_key);
            self.error = None;
            return;
        }
        if self.key.is_some() {
            std::mem::swap(&mut self.contact.patches, &mut self.saved);
            self.saved_key = self.key;
        }
        let result = if warm {
            contact.evaluate_warm(side, &key.pose, &key.vel, &mut self.warm, &mut self.contact)
        } else {
            contact.evaluate(side, &key.pose, &key.vel, &mut self.contact)
        };
        self.error = result.err();
        self.key = if self.error.is_none() {
            Some(key)
        } else {
            None
        };
    }

    /// Forgets the warm start and the reusable evaluations.
    fn invalidate(&mut self) {
        self.warm.invalidate();
        self.key = None;
        self.saved_key = None;
    }
}

/// One wheel's buffers of the contact stage: the evaluation on the rails under it, and while the
/// wheel is in a rail transition (`TrackModel::rail_blend_at`) a second one on the section
/// before's rails.
#[derive(Default)]
struct WheelContact {
    main: ContactSlot,
    partner: ContactSlot,
    /// the section the partner was last evaluated on
    partner_section: usize,
}

/// Where one rail is, moved by the track irregularities and an elastic support's displacement:
/// origin in the y–z plane of the wheelset's track frame and roll about its x-axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailFrame {
    /// \[m\] (y, z) of the rail frame's origin.
    pub origin: [f64; 2],
    /// \[rad\] roll of the rail frame (cross level over the cant base).
    pub roll: f64,
    /// sin and cos of `roll`
    sin_cos: (f64, f64),
}

impl Default for RailFrame {
    /// The track frame itself (rigid rails without irregularities).
    fn default() -> RailFrame {
        RailFrame {
            origin: [0.0; 2],
            roll: 0.0,
            sin_cos: (0.0, 1.0),
        }
    }
}

impl RailFrame {
    /// A vector given in the rail frame's axes (x, y, z), in the wheelset's track frame's axes.
    #[inline]
    pub fn to_track(&self, v: [f64; 3]) -> [f64; 3] {
        let (sd, cd) = self.sin_cos;
        [v[0], cd * v[1] - sd * v[2], sd * v[1] + cd * v[2]]
    }

    /// sin and cos of the roll.
    pub fn sin_cos(&self) -> (f64, f64) {
        self.sin_cos
    }
}

/// Express a wheelset's contact pose and velocities relative to the rail of `side` at track
/// position `s` (in place), the rails being moved by the track's irregularities and by the
/// elastic displacement of the rail's support: lateral alignment and vertical level move both
/// rails, half the gauge deviation moves each rail outward, cross level rolls the rail pair
/// about the centre line, and `support` = (y, z, vy, vz) \[m, m/s\] (zero on rigid rails) moves
/// this rail (an out-of-round wheel's radius deviation is given here too,
/// [`SimModel::wheel_support`]). Returns the rail frame (identity on a rigid track without
/// irregularities and a zero `support`, which are then not evaluated).
#[allow(clippy::too_many_arguments)]
pub fn rail_frame(
    m: &SimModel,
    side: Side,
    s: f64,
    v: f64,
    radius: f64,
    support: [f64; 4],
    pose: &mut WheelsetPose,
    vel: &mut WheelsetVelocity,
) -> RailFrame {
    // (`slope`: this rail's lateral slope d(alignment ± gauge/2)/ds, the angle the rail is turned
    // by about z)
    let (mut o, mut od, delta, ddelta, slope) = match m.track.irregularities() {
        Some(irr) => {
            let ir = irr.at(s);
            let sg = if side == Side::Left { 1.0 } else { -1.0 };
            let slope = ir.dlateral_ds + 0.5 * sg * ir.dgauge_ds;
            (
                [ir.lateral + 0.5 * sg * ir.gauge, ir.vertical],
                [v * slope, v * ir.dvertical_ds],
                ir.cross_level / m.cant_base,
                v * ir.dcross_level_ds / m.cant_base,
                slope,
            )
        }
        None if support == [0.0; 4] => return RailFrame::default(),
        None => ([0.0; 2], [0.0; 2], 0.0, 0.0, 0.0),
    };
    o = [o[0] + support[0], o[1] + support[1]];
    od = [od[0] + support[2], od[1] + support[3]];
    // Axle centre relative to the rail frame's origin, rotated by −δ.
    let c = [pose.y - o[0], pose.z + radius - o[1]];
    let (sd, cd) = delta.sin_cos();
    let cr = [cd * c[0] + sd * c[1], -sd * c[0] + cd * c[1]];
    // Velocity relative to the moving, rolling rail frame.
    let vr = [
        vel.vy - od[0] + ddelta * c[1],
        vel.vz - od[1] - ddelta * c[0],
    ];
    pose.y = cr[0];
    pose.z = cr[1] - radius;
    pose.roll -= delta;
    // The alignment turns the rail by its slope as well as moving it: the wheelset's yaw is
    // taken from the rail's direction, as its lateral velocity is taken from the rail's moving
    // cross-section (V·slope above). Without it a wheelset that follows a skewed rail, moving
    // sideways at V·slope and yawed by the slope, had a lateral creepage of −slope (until stop
    // 38, found by a review: some 4e-4 on ERRI B176's low level). (The rail's turning rate as
    // the contact runs along it, V·d(slope)/ds, a curvature of the alignment, is left out of
    // the yaw rate; it is of the order of 1e-4 1/m on such track against the curve's 1/R.)
    pose.yaw -= slope;
    vel.vy = cd * vr[0] + sd * vr[1];
    vel.vz = -sd * vr[0] + cd * vr[1];
    vel.roll_rate -= ddelta;
    RailFrame {
        origin: o,
        roll: delta,
        sin_cos: (sd, cd),
    }
}

/// The model with its workspace: an [`OdeSystem`].
pub struct Dynamics<'m> {
    /// The model.
    pub model: &'m SimModel,
    /// The workspace.
    pub ws: Workspace,
}

/// Orientation of a track frame: `Rz(heading) · Ry(−atan(gradient)) · Rx(roll)`.
fn track_orientation(heading: f64, gradient: f64, roll: f64) -> M3 {
    mat_mul(
        &mat_mul(&rot_z(heading), &rot_y(-gradient.atan())),
        &rot_x(roll),
    )
}

/// The rates of a body's relative angular velocity `rel` \[rad/s\] (components in its track
/// frame) from Euler's equations `I ω̇ + ω × I ω = M` with `ω = w + rel`: `w` and `wd` are the
/// frame's angular velocity and acceleration, `moment` the moment about the centre of gravity,
/// `inertia` and its inverse in frame axes (all frame components). Since the frame turns at `w`,
/// `ω̇ = wd + d(rel)/dt + w × rel`.
pub fn relative_angular_acceleration(
    inertia: &M3,
    inertia_inv: &M3,
    w: V3,
    wd: V3,
    rel: V3,
    moment: V3,
) -> V3 {
    let om = add(w, rel);
    let h = mul(inertia, om);
    let od = mul(inertia_inv, sub(moment, cross(om, h)));
    sub(sub(od, wd), cross(w, rel))
}

/// The rates of a wheelset's roll, spin and yaw rates `rel` = (φ̇, Ω, ψ̇) \[rad/s\] (components
/// in its track frame) for an axisymmetric rotor with principal moments `ii` = (I_x, I_y, I_z),
/// in its non-spinning axle frame (the carrier, rate ω_c = (w_x + φ̇, w_y, w_z + ψ̇)):
/// ḣ + ω_c × h = M with h = (I_x ω_c,x, I_y Ω_abs, I_z ω_c,z), Ω_abs = w_y + Ω. `w`, `wd` are
/// the frame's angular velocity and acceleration, `moment` the moment about the centre of
/// gravity (frame components). The roll and yaw rates are components in the frame, which turns
/// at `w`, hence −w × (φ̇, 0, ψ̇) as in [`relative_angular_acceleration`]; the spin's own share of
/// that term is of the order left out of Ω_abs (angle × w) and is left out with it. Gives the
/// gyroscopic couples I_y Ω ψ̇ in roll and −I_y Ω φ̇ in yaw (Iwnicki (ed.), *Handbook of Railway
/// Vehicle Dynamics*, ch. 7); docs/models/dynamics.md, "Equations of motion".
pub fn wheelset_angular_acceleration(ii: V3, w: V3, wd: V3, rel: V3, moment: V3) -> V3 {
    let wc = [w[0] + rel[0], w[1], w[2] + rel[2]];
    let h = [ii[0] * wc[0], ii[1] * (w[1] + rel[1]), ii[2] * wc[2]];
    let rhs = sub(moment, cross(wc, h));
    let mut turn = cross(w, [rel[0], 0.0, rel[2]]);
    turn[1] = 0.0;
    let mut od = [0.0; 3];
    for j in 0..3 {
        od[j] = rhs[j] / ii[j] - wd[j] - turn[j];
    }
    od
}

/// \[rad/s²\] a body's absolute angular acceleration (global components) from its frame's
/// orientation `frame`, angular velocity `w` and acceleration `wd` and its relative rates `rel`
/// and their rates `rel_acc` (frame components): the rate of ω = R (w + rel), in which the
/// relative rates turn with the frame, R (ẇ + rel_acc + w × rel). (The turning term was left
/// out before stop 38: some 4e-3 m/s² at an accelerometer off the body's centre.)
pub fn absolute_angular_acceleration(frame: &M3, w: V3, wd: V3, rel: V3, rel_acc: V3) -> V3 {
    mul(frame, add(add(wd, rel_acc), cross(w, rel)))
}

/// The motion of a track frame carried along the track (global components).
#[derive(Debug, Clone, Copy)]
pub struct FrameMotion {
    /// Orientation (columns: the frame's axes).
    pub frame: M3,
    /// \[1/m\] Darboux vector: the frame's angular velocity per metre run.
    pub darboux: V3,
    /// \[rad/s\] angular velocity.
    pub omega: V3,
    /// \[rad/s²\] angular acceleration.
    pub alpha: V3,
    /// \[m/s\] velocity of the origin.
    pub vel_origin: V3,
    /// \[m/s²\] acceleration of the origin.
    pub accel_origin: V3,
}

/// The motion of the track frame `tf` when it moves along the track at `speed` \[m/s\] with
/// `vdot` \[m/s²\] its rate.
///
/// The frame is `Rz(ψ) Ry(−atan g) Rx(φ)` (heading, gradient, roll), so its angular velocity
/// per metre is the Darboux vector `D = κ e_z − α' l + φ' t`, with `l = Rz e_y` the heading's
/// lateral axis, `t` the frame's tangent and `α' = g'/(1 + g²)` the rate of the inclination
/// (`g'` the vertical curvature). Then `ω = v D`, `α = v̇ D + v² dD/ds`, the origin's velocity
/// `v t` and its acceleration `v̇ t + v² D × t`, where `dD/ds` carries the rates of the
/// components and of the axes they refer to (`dl/ds = κ e_z × l`, `dt/ds = D × t`):
/// `dD/ds = κ' e_z − α'' l − α' κ e_z × l + φ'' t + φ' D × t`, with
/// `α'' = −2 g g'²/(1 + g²)²`. Left out: the rate of the vertical curvature itself, zero inside
/// a vertical curve and a jump at its ends (as κ' is at a clothoid's). Source: the kinematics
/// of a frame moving along a space curve (Frenet–Serret / Darboux frame, e.g. do Carmo,
/// *Differential Geometry of Curves and Surfaces*, 1976, §1-5), written here for this frame's
/// angles.
pub fn frame_motion(tf: &TrackFrame, speed: f64, vdot: f64) -> FrameMotion {
    let frame = track_orientation(tf.heading, tf.gradient, tf.roll);
    let tangent = [frame[0][0], frame[1][0], frame[2][0]];
    let rz = rot_z(tf.heading);
    let lateral = [rz[0][1], rz[1][1], rz[2][1]];
    let up = [0.0, 0.0, 1.0];
    let (g, gv) = (tf.gradient, tf.vertical_curvature);
    let g2 = 1.0 + g * g;
    let dalpha = gv / g2;
    let darboux = add(
        add(scale(tf.curvature, up), scale(-dalpha, lateral)),
        scale(tf.droll_ds, tangent),
    );
    let d_tangent = cross(darboux, tangent);
    let ddalpha = -2.0 * g * gv * gv / (g2 * g2);
    let d_darboux = add(
        add(
            add(scale(tf.dcurvature_ds, up), scale(-ddalpha, lateral)),
            scale(-dalpha * tf.curvature, cross(up, lateral)),
        ),
        add(scale(tf.droll_ds2, tangent), scale(tf.droll_ds, d_tangent)),
    );
    FrameMotion {
        frame,
        darboux,
        omega: scale(speed, darboux),
        alpha: add(scale(vdot, darboux), scale(speed * speed, d_darboux)),
        vel_origin: scale(speed, tangent),
        // the frame's own ẍ·t is the member's longitudinal acceleration, left out here
        accel_origin: add(scale(vdot, tangent), scale(speed * speed, d_tangent)),
    }
}

impl<'m> Dynamics<'m> {
    /// The model with a fresh workspace.
    pub fn new(model: &'m SimModel) -> Self {
        Dynamics {
            model,
            ws: Workspace::new(model),
        }
    }
}

impl Dynamics<'_> {
    /// Stages 1–3: frames and kinematics of every member.
    fn kinematics(&mut self, t: f64, x: &[f64]) {
        let m = self.model;
        let (d, v, vdot) = m.motion(t);
        let s = m.start + d;
        self.ws.track_position = s;
        self.ws.speed = v;
        for (i, mm) in m.members.iter().enumerate() {
            let mut q = [0.0; 6];
            let mut qd = [0.0; 6];
            for k in 0..6 {
                q[k] = m.coord(i, k, x);
                qd[k] = m.coord_rate(i, k, x, v);
            }
            // The member's frame follows the track at the member's own position s + x0 + x,
            // moving at V + ẋ: its coordinate x is the frame's lead, so the contact always sees
            // the track where the member is.
            let tf = m.track.frame_at(s + mm.p0[0] + q[0]);
            let FrameMotion {
                frame,
                darboux,
                omega: omega_frame,
                alpha: alpha_frame,
                vel_origin,
                accel_origin,
            } = frame_motion(&tf, v + qd[0], vdot);
            let wheelset = mm.is_wheelset();
            if wheelset {
                q[4] = 0.0;
            }
            let r_local = [0.0, mm.p0[1] + q[1], mm.p0[2] + q[2]];
            let cog = add(tf.position_g, mul(&frame, r_local));
            let rel_vel = [0.0, qd[1], qd[2]];
            let vel = add(
                add(vel_origin, cross(omega_frame, mul(&frame, r_local))),
                mul(&frame, rel_vel),
            );
            let orient = mat_mul(&frame, &rotation_rpy(q[3], q[4], q[5]));
            let rel_rate = [qd[3], if wheelset { 0.0 } else { qd[4] }, qd[5]];
            let omega = add(omega_frame, mul(&frame, rel_rate));
            self.ws.kin[i] = MemberKin {
                frame,
                origin: tf.position_g,
                darboux,
                omega_frame,
                alpha_frame,
                accel_origin,
                vel_origin,
                q,
                qd,
                r_local,
                cog,
                vel,
                orient,
                omega,
                force: [0.0; 3],
                moment: [0.0; 3],
                accel: [0.0; 3],
                alpha: [0.0; 3],
            };
        }
    }

    /// Position, velocity, orientation and angular velocity of an element's end `e` at vehicle
    /// point `a`; a track end uses the frame of the member at the other end.
    fn end_state(&self, e: End, other: End, a: V3) -> (V3, V3, M3, V3) {
        match (e, other) {
            (End::Member(i), _) => {
                let k = &self.ws.kin[i.0];
                let arm = mul(&k.orient, sub(a, self.model.members[i.0].p0));
                (
                    add(k.cog, arm),
                    add(k.vel, cross(k.omega, arm)),
                    k.orient,
                    k.omega,
                )
            }
            (End::Track, End::Member(j)) => {
                let k = &self.ws.kin[j.0];
                let p0 = self.model.members[j.0].p0;
                // A point fixed to the track-following frame at s + a_x (not moving with the
                // member's lead x): it moves at V, not V + ẋ.
                let arm = mul(&k.frame, [a[0] - p0[0] - k.q[0], a[1], a[2]]);
                let tangent = [k.frame[0][0], k.frame[1][0], k.frame[2][0]];
                (
                    add(k.origin, arm),
                    sub(
                        add(k.vel_origin, cross(k.omega_frame, arm)),
                        scale(k.qd[0], tangent),
                    ),
                    k.frame,
                    k.omega_frame,
                )
            }
            (End::Track, End::Track) => unreachable!("rejected when the model is built"),
        }
    }

    /// A failed evaluation at `t`: `body` and `quantity` kept for the stop error
    /// (`Workspace::failure`), and the integrator's error.
    fn fail(&mut self, t: f64, body: String, quantity: String) -> RhsError {
        let message = format!("t = {t:.6} s: {body}: {quantity}");
        self.ws.failure = Some((body, quantity));
        RhsError(message)
    }

    /// Stage 4: force elements, the friction elements last (`SimModel::element_order`: their
    /// sliding force may depend on another element's force). Writes the internal-state rates
    /// into `dx`.
    /// Fails when an element along its line has its points within [`LINE_COLLAPSE`] (its
    /// direction would be lost; the run stops naming the element).
    fn elements(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        let model = self.model;
        for &ei in &model.element_order {
            self.element(t, ei, &model.elements[ei], x, dx)?;
        }
        Ok(())
    }

    /// One force element `el` (number `ei`): its forces on the members, its state rate.
    fn element(
        &mut self,
        t: f64,
        ei: usize,
        el: &ElementModel,
        x: &[f64],
        dx: &mut [f64],
    ) -> Result<(), RhsError> {
        let (p1, v1, q1, w1) = self.end_state(el.ends[0], el.ends[1], el.points[0]);
        let (p2, v2, q2, w2) = self.end_state(el.ends[1], el.ends[0], el.points[1]);
        let dp = sub(p2, p1);
        // Deflections in body 1's axes, then the element's local axes; along the line between
        // the points, the change of their distance and its rate (local x), with `line_dir`
        // the line's direction now.
        let e = &el.axes;
        let (lin, lin_rate, line_dir) = match el.line {
            None => (
                mul_t(e, sub(mul_t(&q1, dp), sub(el.points[1], el.points[0]))),
                mul_t(e, mul_t(&q1, sub(sub(v2, v1), cross(w1, dp)))),
                None,
            ),
            Some(l0) => {
                let l = dot(dp, dp).sqrt();
                // (false for NaN: a non-finite state is the integrator's to report)
                if l < LINE_COLLAPSE {
                    return Err(self.fail(
                        t,
                        format!("element '{}'", el.name),
                        format!(
                            "its points came {:.3} mm apart (nominal {:.3} m): an element along the line between its points needs them at least {} mm apart",
                            l * 1e3,
                            l0,
                            LINE_COLLAPSE * 1e3
                        ),
                    ));
                }
                let u = scale(1.0 / l, dp);
                ([l - l0, 0.0, 0.0], [dot(u, sub(v2, v1)), 0.0, 0.0], Some(u))
            }
        };
        let rot = mul_t(e, small_rotation(&mat_t_mul(&q1, &q2)));
        let rot_rate = mul_t(e, mul_t(&q1, sub(w2, w1)));
        let mut f = [0.0; 3];
        let mut mo = [0.0; 3];
        let (mut sliding, mut sliding_moment) = (None, None);
        match &el.law {
            ForceLaw::Bushing { stiffness, damping } => {
                for k in 0..3 {
                    f[k] = -stiffness[k] * lin[k] - damping[k] * lin_rate[k];
                    mo[k] = -stiffness[3 + k] * rot[k] - damping[3 + k] * rot_rate[k];
                }
            }
            ForceLaw::Table { axis, table } => {
                let k = axis.index();
                f[k] = -table.force(lin[k]);
            }
            ForceLaw::SeriesSpringDamper {
                axis,
                stiffness,
                damping,
            } => {
                let k = axis.index();
                let i = el.internal.expect("series elements carry a state");
                let s = x[i];
                f[k] = series_force(*stiffness, lin[k], s);
                dx[i] = series_state_rate(*stiffness, *damping, lin[k], s);
                self.ws.series_delta[ei][0] = lin[k];
            }
            ForceLaw::AntiRollBar { stiffness } => {
                mo[Axis::X.index()] = -stiffness * rot[0];
            }
            ForceLaw::Damper {
                axis,
                table,
                stiffness,
            } => {
                let k = axis.index();
                match (stiffness, el.internal) {
                    (Some(ks), Some(i)) => {
                        (f[k], dx[i]) = damper_series_law(table, *ks, lin[k], x[i]);
                        self.ws.series_delta[ei][0] = lin[k];
                    }
                    _ => f[k] = -table.force(lin_rate[k]),
                }
            }
            ForceLaw::Friction {
                axis,
                rotational,
                stiffness,
                force,
                coefficient,
                normal,
            } => {
                let k = axis.index();
                let i = el.internal.expect("friction elements carry a state");
                // (the normal element comes earlier in `element_order`)
                let load = normal.map_or(0.0, |n| n.load(self.ws.element_force[n.element.index()]));
                let f0 = force + coefficient * load;
                if *rotational {
                    (mo[k], dx[i]) = friction_law(*stiffness, f0, rot[k], rot_rate[k], x[i]);
                    self.ws.series_delta[ei][0] = rot[k];
                    sliding_moment = Some(f0);
                } else {
                    (f[k], dx[i]) = friction_law(*stiffness, f0, lin[k], lin_rate[k], x[i]);
                    self.ws.series_delta[ei][0] = lin[k];
                    sliding = Some(f0);
                }
            }
            ForceLaw::PlanarFriction {
                axes,
                stiffness,
                force,
                coefficient,
                normal,
            } => {
                let [a, b] = [axes[0].index(), axes[1].index()];
                let i = el
                    .internal
                    .expect("planar friction elements carry two states");
                let load = normal.map_or(0.0, |n| n.load(self.ws.element_force[n.element.index()]));
                let f0 = force + coefficient * load;
                let (fo, rate) = planar_friction_law(
                    *stiffness,
                    f0,
                    [lin[a], lin[b]],
                    [lin_rate[a], lin_rate[b]],
                    [x[i], x[i + 1]],
                );
                (f[a], f[b]) = (fo[0], fo[1]);
                (dx[i], dx[i + 1]) = (rate[0], rate[1]);
                self.ws.series_delta[ei] = [lin[a], lin[b]];
                sliding = Some(f0);
            }
        }
        // The static preload: the law gives the force beyond it, from the nominal geometry.
        for k in 0..3 {
            f[k] += el.preload[k];
            mo[k] += el.preload[3 + k];
        }
        self.ws.element_force[ei] = f;
        if self.ws.record {
            let states = el.law.internal_states();
            let mut state = [0.0; 2];
            if let Some(i) = el.internal {
                state[..states].copy_from_slice(&x[i..i + states]);
            }
            self.ws.elements[ei] = ElementRecord {
                deflection: lin,
                rate: lin_rate,
                rotation: rot,
                force: f,
                moment: mo,
                state,
                states,
                sliding_force: sliding,
                sliding_moment,
                power: -(dot(f, lin_rate) + dot(mo, rot_rate)),
                dissipation: dissipation(
                    &el.law,
                    el.internal.map(|i| &dx[i..]),
                    f,
                    mo,
                    lin_rate,
                    rot_rate,
                ),
            };
        }
        // (along the line: on it, and no moment; body 1's reaction at P2 is then the same as at
        // P1, the line passing through both)
        let force = match line_dir {
            None => mul(&q1, mul(e, f)),
            Some(u) => scale(f[0], u),
        };
        let moment = mul(&q1, mul(e, mo));
        // Each end's moment about its centre of gravity: body 2's own, body 1's the reaction at
        // the same point, P2 (the massless element passes force and moment through unchanged,
        // so the pair conserves momentum and angular momentum and the element's power above is
        // the work done on the two bodies).
        let end = |e: End, sign: f64| match e {
            End::Member(i) => {
                let k = &self.ws.kin[i.0];
                let mo = scale(sign, add(cross(sub(p2, k.cog), force), moment));
                Some((i, mo))
            }
            _ => None,
        };
        let (m2, m1) = (end(el.ends[1], 1.0), end(el.ends[0], -1.0));
        // A wheelset's elements act on its axle boxes, which sit on bearings: the moment about
        // its own axle (the non-spinning axle frame's y, rolled and yawed with it) does not
        // reach its spin. The boxes' pitch is taken as held by the other body (as in multibody
        // models without axle-box bodies), so that body takes it back, as a couple, and the
        // pair still conserves angular momentum.
        let axial = |m: Option<(MemberIx, V3)>| -> V3 {
            match m {
                Some((i, mo)) if self.model.members[i.0].is_wheelset() => {
                    let o = &self.ws.kin[i.0].orient;
                    let axle = [o[0][1], o[1][1], o[2][1]];
                    scale(dot(mo, axle), axle)
                }
                _ => [0.0; 3],
            }
        };
        let (a2, a1) = (axial(m2), axial(m1));
        if let Some((i, mo)) = m2 {
            let k = &mut self.ws.kin[i.0];
            k.force = add(k.force, force);
            k.moment = add(k.moment, sub(add(mo, a1), a2));
        }
        if let Some((i, mo)) = m1 {
            let k = &mut self.ws.kin[i.0];
            k.force = sub(k.force, force);
            k.moment = add(k.moment, sub(add(mo, a2), a1));
        }
        Ok(())
    }

    /// Stage 5: contact of every wheel: the inputs in order, the evaluations in parallel (rayon;
    /// each wheel in its own workspace, with its own warm start, so the result does not depend
    /// on the threads), the forces on the wheelsets in the wheels' order.
    fn contact(&mut self, t: f64, x: &[f64]) -> Result<(), RhsError> {
        let m = self.model;
        // Set by `kinematics` for this evaluation.
        let (s, v) = (self.ws.track_position, self.ws.speed);
        self.ws.patches.clear();
        for (wi, wheel) in m.wheels.iter().enumerate() {
            let mi = wheel.member.0;
            let mm = &m.members[mi];
            let radius = match mm.kind {
                MemberKind::Wheelset { radius, .. } => radius,
                MemberKind::Body => unreachable!("wheels belong to wheelsets"),
            };
            let k = &self.ws.kin[mi];
            // Frame components: axle centre, its absolute velocity and the carrier's angular
            // velocity (the spin separately), less the frame's roll rate (the cant's rate along
            // a transition, V φ′) and its share ω_x e_x × r: the rails' cross-section rolls with
            // the frame as the wheel runs along it, and the contact takes the rail as prismatic,
            // so the wheel's velocity is taken relative to that rolling section, as the
            // irregularities' cross level is (`rail_frame`). Left in, the rails' own rise,
            // ±V φ′ b at the wheels, reached the patches as a lateral slip φ′ b sin δ (up to 8e-4
            // at a flange in the R = 150 m curve's transition; stop 38's review). The frame's
            // yaw and pitch rates stay: the curve's yaw makes real slip (the outer rail is
            // longer).
            let omega_l = mul_t(&k.frame, k.omega_frame);
            let r = k.r_local;
            let twist = [omega_l[0], 0.0, 0.0];
            let v_l = add(
                add([v + k.qd[0], 0.0, 0.0], cross(sub(omega_l, twist), r)),
                [0.0, k.qd[1], k.qd[2]],
            );
            let mut pose = WheelsetPose {
                y: r[1],
                z: r[2] - radius,
                roll: k.q[3],
                yaw: k.q[5],
            };
            let mut vel = WheelsetVelocity {
                vx: v_l[0],
                vy: v_l[1],
                vz: v_l[2],
                roll_rate: k.qd[3],
                yaw_rate: omega_l[2] + k.qd[5],
                spin: omega_l[1] + k.qd[4],
            };
            let s_wheel = s + mm.p0[0] + k.q[0];
            let lag = mm.rolled_angle.map_or(0.0, |i| x[i]);
            let (support, lead) =
                m.wheel_support(wi, m.rail_state(wi, x), (s_wheel, radius, lag), &mut vel);
            let rail = rail_frame(
                m, wheel.side, s_wheel, v, radius, support, &mut pose, &mut vel,
            );
            // Other rails under the wheel: the warm start describes the other pair. In a
            // transition the section before's rails are evaluated too (`WheelContact::partner`).
            let blend = m.track.rail_blend_at(s_wheel);
            let section = blend.section;
            let slots = &mut self.ws.wheel_contact[wi];
            if section != self.ws.wheel_input[wi].section {
                slots.main.warm.invalidate();
            }
            // (`rail_blend_at` gives a weight below 1 only from the second section on)
            let blended = blend.weight < 1.0 && section > 0;
            if blended && slots.partner_section != section - 1 {
                slots.partner.warm.invalidate();
                slots.partner_section = section - 1;
            }
            self.ws.wheel_input[wi] = WheelInput {
                pose,
                vel,
                rail,
                r,
                section,
                weight: if blended { blend.weight } else { 1.0 },
                lead,
            };
        }
        let timer = self.ws.timing.then(Instant::now);
        let inputs = &self.ws.wheel_input;
        let evaluate = |(wi, slots): (usize, &mut WheelContact)| {
            let (wheel, inp) = (&m.wheels[wi], &inputs[wi]);
            let one = |section: usize, slot: &mut ContactSlot| {
                let key = EvalKey {
                    section,
                    pose: inp.pose,
                    vel: inp.vel,
                };
                slot.evaluate(&wheel.contacts[section], wheel.side, key, m.warm_start);
            };
            one(inp.section, &mut slots.main);
            if inp.weight < 1.0 {
                one(inp.section - 1, &mut slots.partner);
            } else {
                slots.partner.error = None;
            }
        };
        // In parallel only on a thread of a rayon pool (the CLI runs its commands in one): the
        // calling thread then takes a share and the others steal the rest. From any other
        // thread a parallel loop would hand the whole evaluation to the pool and wait, which
        // costs more than it saves (docs/performance.md).
        if rayon::current_thread_index().is_some() {
            self.ws
                .wheel_contact
                .par_iter_mut()
                .enumerate()
                .for_each(evaluate);
        } else {
            self.ws
                .wheel_contact
                .iter_mut()
                .enumerate()
                .for_each(evaluate);
        }
        if let Some(t0) = timer {
            self.ws.cost.contact += t0.elapsed().as_secs_f64();
        }
        for (wi, wheel) in m.wheels.iter().enumerate() {
            let mi = wheel.member.0;
            let slots = &mut self.ws.wheel_contact[wi];
            let error = slots.main.error.take();
            if let Some(e) = error.or_else(|| slots.partner.error.take()) {
                let body = format!(
                    "wheelset '{}', {} wheel",
                    m.members[mi].name,
                    wheel.side.name()
                );
                return Err(self.fail(t, body, format!("contact: {e}")));
            }
            let WheelInput {
                rail,
                r,
                weight,
                lead,
                ..
            } = self.ws.wheel_input[wi];
            let frame = self.ws.kin[mi].frame;
            let o = rail.origin;
            let back = |p: [f64; 3]| rail.to_track(p);
            let mut total = [0.0; 3];
            let mut force_g = [0.0; 3];
            let mut moment_g = [0.0; 3];
            // in a rail transition the patches on both rails, each with its weight
            let slots = &self.ws.wheel_contact[wi];
            let partner = &slots.partner.contact.patches;
            let both = slots
                .main
                .contact
                .patches
                .iter()
                .map(|p| (p, weight))
                .chain(
                    partner
                        .iter()
                        .filter(|_| weight < 1.0)
                        .map(|p| (p, 1.0 - weight)),
                );
            for (p, w) in both {
                let pt = add(back(p.point_track), [0.0, o[0], o[1]]);
                let f = scale(w, back(p.force_track));
                let mo = scale(w, back(p.moment_track));
                // an out-of-round wheel's support point lies `lead` ahead of the axle
                let arm = [pt[0] + lead, pt[1] - r[1], pt[2] - r[2]];
                total = add(total, f);
                force_g = add(force_g, mul(&frame, f));
                moment_g = add(moment_g, mul(&frame, add(cross(arm, f), mo)));
                if self.ws.record {
                    let mut result = *p;
                    result.point_track[0] += lead;
                    self.ws.patches.push(PatchRecord {
                        wheel: wi,
                        result,
                        force_frame: f,
                        weight: w,
                    });
                }
            }
            self.ws.wheel_force[wi] = total;
            let kk = &mut self.ws.kin[mi];
            kk.force = add(kk.force, force_g);
            kk.moment = add(kk.moment, moment_g);
        }
        Ok(())
    }

    /// Stage 6a (wheelsets with an out-of-round wheel only): the rate of each rolled angle's
    /// lag behind its track position, Ω − (V + ẋ)/r0, with Ω the wheelset's absolute spin about
    /// its axle (as the contact takes it) and r0 its nominal radius
    /// (`MemberModel::rolled_angle`).
    fn rolled_angles(&mut self, dx: &mut [f64]) {
        let m = self.model;
        let v = self.ws.speed;
        for (mi, mm) in m.members.iter().enumerate() {
            let (Some(i), MemberKind::Wheelset { radius, .. }) = (mm.rolled_angle, mm.kind) else {
                continue;
            };
            let k = &self.ws.kin[mi];
            let spin = mul_t(&k.frame, k.omega_frame)[1] + k.qd[4];
            dx[i] = spin - (v + k.qd[0]) / radius;
        }
    }

    /// Stage 6 (elastic rail support only): each rail mass under the reaction of its wheel's
    /// contact force and its support's spring and damper, in the wheelset's track frame
    /// (`docs/models/track.md`, "Elastic rail support").
    fn rails(&mut self, x: &[f64], dx: &mut [f64]) {
        let m = self.model;
        let Some(sup) = m.rail_support else {
            return;
        };
        for (wi, wheel) in m.wheels.iter().enumerate() {
            let Some(i) = wheel.rail else { continue };
            let [y, z, vy, vz] = m.rail_state(wi, x);
            let f = self.ws.wheel_force[wi];
            dx[i] = vy;
            dx[i + 1] = vz;
            dx[i + 2] = (-f[1] - sup.lateral_stiffness * y - sup.lateral_damping * vy) / sup.mass;
            dx[i + 3] = (-f[2] - sup.vertical_stiffness * z - sup.vertical_damping * vz) / sup.mass;
        }
    }

    /// Stage 7: accelerations in each member's frame.
    fn equations(&mut self, dx: &mut [f64]) {
        let m = self.model;
        // A wheelset's traction or brake torque acts about its axle (below); its reaction, where
        // the vehicle names a mount, acts on that body about the same axis.
        for (i, mm) in m.members.iter().enumerate() {
            if let Some(MemberIx(b)) = mm.torque_reaction {
                let fr = &self.ws.kin[i].frame;
                let axle = [fr[0][1], fr[1][1], fr[2][1]];
                let k = &mut self.ws.kin[b];
                k.moment = add(k.moment, scale(-mm.torque, axle));
            }
        }
        for (i, mm) in m.members.iter().enumerate() {
            let k = &mut self.ws.kin[i];
            let fr = &k.frame;
            let g_l = mul_t(fr, [0.0, 0.0, -m.gravity * mm.mass]);
            let f_l = add(mul_t(fr, k.force), g_l);
            let mut m_l = mul_t(fr, k.moment);
            // Traction or brake torque about the axle.
            m_l[1] += mm.torque;
            let w = mul_t(fr, k.omega_frame);
            let wd = mul_t(fr, k.alpha_frame);
            let r = k.r_local;
            let rd = [0.0, k.qd[1], k.qd[2]];
            // Acceleration of a point fixed at r in the moving frame, plus Coriolis.
            let a_frame = add(
                add(mul_t(fr, k.accel_origin), cross(wd, r)),
                add(cross(w, cross(w, r)), scale(2.0, cross(w, rd))),
            );
            let mut acc = [0.0; 6];
            for j in 0..3 {
                acc[j] = f_l[j] / mm.mass - a_frame[j];
            }
            match mm.kind {
                MemberKind::Body => {
                    let rel = [k.qd[3], k.qd[4], k.qd[5]];
                    let od = relative_angular_acceleration(
                        &mm.inertia,
                        &mm.inertia_inv,
                        w,
                        wd,
                        rel,
                        m_l,
                    );
                    acc[3..6].copy_from_slice(&od);
                }
                MemberKind::Wheelset { .. } => {
                    let ii = [mm.inertia[0][0], mm.inertia[1][1], mm.inertia[2][2]];
                    let rel = [k.qd[3], k.qd[4], k.qd[5]];
                    let od = wheelset_angular_acceleration(ii, w, wd, rel, m_l);
                    acc[3..6].copy_from_slice(&od);
                }
            }
            // absolute accelerations, for the samples' accelerometers only
            if self.ws.record {
                let rel = |j: usize| if mm.rate[j].is_some() { acc[j] } else { 0.0 };
                k.accel = mul(fr, add(a_frame, [rel(0), rel(1), rel(2)]));
                if mm.kind == MemberKind::Body {
                    k.alpha = absolute_angular_acceleration(
                        fr,
                        w,
                        wd,
                        [k.qd[3], k.qd[4], k.qd[5]],
                        [rel(3), rel(4), rel(5)],
                    );
                }
            }
            for j in 0..6 {
                if let Some(ix) = mm.rate[j] {
                    dx[ix] = acc[j];
                }
                if let Some(ix) = mm.pos[j] {
                    dx[ix] = k.qd[j];
                }
            }
        }
    }
}

impl OdeSystem for Dynamics<'_> {
    fn dim(&self) -> usize {
        self.model.dim()
    }

    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        let t0 = self.ws.timing.then(Instant::now);
        self.kinematics(t, x);
        let ts = self.ws.timing.then(Instant::now);
        self.elements(t, x, dx)?;
        if let Some(ts) = ts {
            self.ws.cost.suspension += ts.elapsed().as_secs_f64();
        }
        self.contact(t, x)?;
        self.rails(x, dx);
        self.rolled_angles(dx);
        self.equations(dx);
        if let Some(t0) = t0 {
            self.ws.cost.rhs += t0.elapsed().as_secs_f64();
        }
        self.ws.cost.evaluations += 1;
        Ok(())
    }

    fn abs_tol_scale(&self, i: usize) -> f64 {
        let m = self.model;
        if i < m.n_pos {
            1.0
        } else if i < m.n_pos + m.n_rate {
            // Rates: 10 × the positions' scale; spin rates (~100 rad/s) 1000.
            let is_spin = m
                .members
                .iter()
                .any(|mm| mm.is_wheelset() && mm.rate[4] == Some(i));
            if is_spin { 1000.0 } else { 10.0 }
        } else {
            1.0
        }
    }

    fn jacobian_pattern(&self) -> Option<railsim_ode::JacobianPattern> {
        Some(self.model.jacobian_pattern())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The absolute angular acceleration against a centred difference of ω(t) = R(t)(w + rel(t))
    /// for a frame turning at Ω = 0.4 rad/s about z (R = Rz(Ω t)) and a body whose relative roll
    /// rate grows at 2 rad/s² and relative yaw rate is 0.3 rad/s: to 1e-7; without the turning
    /// term w × rel the difference is Ω × (2 t, 0, 0.3)'s 0.8 t rad/s².
    #[test]
    fn the_absolute_angular_acceleration_is_the_rate_of_the_angular_velocity() {
        let (big, a) = (0.4, 2.0);
        let omega_at = |t: f64| {
            let r = rot_z(big * t);
            mul(&r, [a * t, 0.0, big + 0.3])
        };
        for t in [0.3, 1.0, 2.5] {
            let h = 1e-5;
            let d = scale(0.5 / h, sub(omega_at(t + h), omega_at(t - h)));
            let got = absolute_angular_acceleration(
                &rot_z(big * t),
                [0.0, 0.0, big],
                [0.0; 3],
                [a * t, 0.0, 0.3],
                [a, 0.0, 0.0],
            );
            let e = sub(got, d);
            assert!(dot(e, e).sqrt() < 1e-7, "t {t}: {got:?} against {d:?}");
            let plain = mul(&rot_z(big * t), [a, 0.0, 0.0]);
            let miss = sub(plain, d);
            assert!(dot(miss, miss).sqrt() > 0.5 * big * a * t, "t {t}");
        }
    }
}
