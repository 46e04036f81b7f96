//! The simulation model compiled from a [`Scene`]: members (bodies and wheelsets) with their
//! state indices, force elements, one contact pair per wheel, and the state layout.
//!
//! Model only what the scene requires: only the degrees of freedom the scene leaves free get
//! state variables, a wheelset's spin angle is never a state (wheelsets are axisymmetric), only
//! series spring-dampers carry internal states, and irregularities are evaluated only when the
//! track has them.

use railsim_contact::{
    ContactOptions, Friction, PairSpec, Side, WheelRailContact, WheelRailPair, WheelsetPose,
    WheelsetVelocity,
};
use railsim_elastic::Material;
use railsim_profile::{Profile, ProfileError, ProfileKind, analytic, read_simpack, read_table_mm};
use railsim_track::{RailProfile, RailSection, RailSupport, TrackModel};
use railsim_vehicle::model::{
    Endpoint, ForceLaw, Member, WheelDefect, WheelProfile, Wheelset, rim_support,
};
use railsim_vehicle::{BOGIE_FRAME_MIN_OFFSET, DofKind, VehicleModel};

use crate::assess::ComfortPoint;
use crate::error::SimError;
use crate::math::{M3, V3, inverse};
use crate::scene::{Scene, SpeedProfile, friction_model};

/// \[Pa\] combined shear modulus of wheel and rail steel (CONTACT's benchmark value).
pub const STEEL_SHEAR_MODULUS: f64 = 82e9;
/// \[-\] Poisson's ratio of wheel and rail steel.
pub const STEEL_POISSON: f64 = 0.28;

/// A typed index into [`SimModel::members`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MemberIx(pub usize);

/// What a member is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MemberKind {
    /// A rigid body (carbody, bogie frame).
    Body,
    /// A wheelset: its rotation about y is the spin, with no angle state.
    Wheelset {
        /// Index of its first wheel in [`SimModel::wheels`] (left, then right).
        first_wheel: usize,
        /// \[m\] nominal rolling radius.
        radius: f64,
    },
}

/// A body or wheelset, with where its coordinates live in the state vector.
#[derive(Debug, Clone)]
pub struct MemberModel {
    /// Name, as in the vehicle file.
    pub name: String,
    /// Body or wheelset.
    pub kind: MemberKind,
    /// \[kg\]
    pub mass: f64,
    /// \[kg m²\] inertia about the centre of gravity, body axes.
    pub inertia: M3,
    /// Its inverse.
    pub inertia_inv: M3,
    /// \[m\] nominal centre of gravity in the vehicle frame; its x places the member's own
    /// track-following frame at s + x.
    pub p0: V3,
    /// Index of each coordinate (x, y, z, roll, pitch, yaw) in the state, `None` if frozen (a
    /// wheelset's pitch never has one).
    pub pos: [Option<usize>; 6],
    /// Index of each rate in the state, `None` if frozen. A frozen wheelset spin rolls at
    /// V / `rolling_radius`.
    pub rate: [Option<usize>; 6],
    /// \[N m\] a wheelset's constant traction (> 0) or brake (< 0) torque about its axle.
    pub torque: f64,
    /// The body that carries the torque's reaction (−torque about the wheelset's axle); `None`:
    /// the reaction acts on nothing modelled.
    pub torque_reaction: Option<MemberIx>,
    /// \[m\] a wheelset's rolling radius in its initial position on the rails (the mean of its
    /// two wheels, from the contact); the nominal radius until the initial state is found.
    pub rolling_radius: f64,
    /// A wheelset with an out-of-round wheel: the state index of its rolled angle's lag behind
    /// its track position, φ = θ − s/r0 \[rad\] (`SimModel::wheel_support`).
    pub rolled_angle: Option<usize>,
}

impl MemberModel {
    /// Whether this member is a wheelset.
    pub fn is_wheelset(&self) -> bool {
        matches!(self.kind, MemberKind::Wheelset { .. })
    }
}

/// One end of a force element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The track-following frame of the other end's member.
    Track,
    /// A member.
    Member(MemberIx),
}

/// A force element, with its ends resolved to members.
#[derive(Debug, Clone)]
pub struct ElementModel {
    /// Name as in the vehicle file.
    pub name: String,
    /// Body 1 and body 2.
    pub ends: [End; 2],
    /// \[m\] attachment points, vehicle frame (nominal).
    pub points: [V3; 2],
    /// Columns: local axes in the vehicle frame.
    pub axes: M3,
    /// The law.
    pub law: ForceLaw,
    /// \[m\] nominal distance between the attachment points of an element that acts along
    /// the line between them (`railsim_vehicle::ForceElement::line`); `None` for the others.
    pub line: Option<f64>,
    /// Index of the (first) internal state in the state vector, if the element has any (a
    /// planar friction has two, one after the other).
    pub internal: Option<usize>,
    /// \[N ×3, N·m ×3\] static preload on body 2, local axes: the element's force in the
    /// vehicle's static equilibrium (`StaticEquilibrium::element_force`), added to its law so
    /// that the nominal (loaded) geometry of the vehicle file is in equilibrium. Set by
    /// `Simulation::new`; zero for the dissipative elements.
    pub preload: [f64; 6],
}

/// One wheel: a contact pair evaluated online.
#[derive(Debug, Clone)]
pub struct WheelModel {
    /// The wheelset.
    pub member: MemberIx,
    /// Wheelset number counted from the front of the vehicle, from 0.
    pub wheelset_number: u32,
    /// Left or right.
    pub side: Side,
    /// Wheel profile on the rail profile of each of the track's rail sections
    /// (`TrackModel::rail_sections`, the same order), evaluated with the scene's contact model.
    pub contacts: Vec<WheelRailContact>,
    /// Index of the first of the four states of the rail under this wheel on an elastic rail
    /// support (lateral and vertical displacement, then their rates); `None` on rigid rails.
    pub rail: Option<usize>,
    /// The wheel's out-of-roundness (empty: a round wheel), met as a vertical displacement of
    /// its rail (`SimModel::wheel_support`).
    pub out_of_roundness: Vec<WheelDefect>,
}

/// The immutable simulation model.
#[derive(Debug, Clone)]
pub struct SimModel {
    /// Bodies first (file order), then wheelsets.
    pub members: Vec<MemberModel>,
    /// Force elements, in file order.
    pub elements: Vec<ElementModel>,
    /// The order in which the right-hand side evaluates the elements: file order, the friction
    /// elements last (their sliding force may be another element's force times a coefficient).
    pub element_order: Vec<usize>,
    /// Two per wheelset, left then right.
    pub wheels: Vec<WheelModel>,
    /// The track.
    pub track: TrackModel,
    /// Speed against distance run.
    pub speed: SpeedProfile,
    /// \[m\] track position of the vehicle reference point at t = 0.
    pub start: f64,
    /// \[m/s²\]
    pub gravity: f64,
    /// \[m\] cant base (distance between the rail contact points that cant is measured over).
    pub cant_base: f64,
    /// Warm-start each wheel's contact search from its previous evaluation.
    pub warm_start: bool,
    /// Number of position states (first in the state vector).
    pub n_pos: usize,
    /// Number of rate states (after the positions).
    pub n_rate: usize,
    /// Number of internal states (after the rates).
    pub n_internal: usize,
    /// The track's elastic rail support, `None` for rigid rails.
    pub rail_support: Option<RailSupport>,
    /// Number of rail states (after the internal states): four per wheel on an elastic rail
    /// support.
    pub n_rail: usize,
    /// Number of rolled-angle states (last): one per wheelset with an out-of-round wheel
    /// (`MemberModel::rolled_angle`).
    pub n_angle: usize,
    /// Names of the state variables, for messages.
    pub state_names: Vec<String>,
    /// The carbody (member index: the heaviest rigid body) and its measuring points
    /// (`crate::assess`): the scene's, or by default its centre and above every other body at
    /// least 0.5 m from it along x (the bogies), at the height of its centre of gravity; `None`
    /// for a vehicle without rigid bodies.
    pub comfort: Option<(usize, Vec<ComfortPoint>)>,
    /// The bogie frames of the simplified stability method (`crate::assess`): the rigid bodies
    /// other than the carbody at least 0.5 m from it along x, each with the wheelsets nearest
    /// to it along x.
    pub bogies: Vec<BogieModel>,
}

/// A bogie frame and where its lateral acceleration is measured.
#[derive(Debug, Clone, PartialEq)]
pub struct BogieModel {
    /// The frame's member index.
    pub member: usize,
    /// \[kg\] the bogie's mass: the frame and its wheelsets.
    pub mass: f64,
    /// Above each of its wheelsets: the point's name and \[m\] its offset from the frame's
    /// centre of gravity (frame axes).
    pub points: Vec<(String, [f64; 3])>,
}

impl SimModel {
    /// Build the model of a compiled scene: the state layout from its free degrees of freedom,
    /// one contact pair per wheel (wheel profile of the vehicle, rail profile of the track).
    pub fn new(scene: &Scene) -> Result<SimModel, SimError> {
        let v: &VehicleModel = &scene.vehicle;
        let free = scene.dofs();
        let mut members = Vec::new();
        for b in v.bodies() {
            members.push(MemberModel {
                name: b.name.clone(),
                kind: MemberKind::Body,
                mass: b.mass,
                inertia: b.inertia,
                inertia_inv: inverse(&b.inertia).ok_or_else(|| SimError::Model {
                    message: format!("body '{}': inertia matrix is singular", b.name),
                })?,
                p0: b.position,
                pos: [None; 6],
                rate: [None; 6],
                torque: 0.0,
                torque_reaction: None,
                rolling_radius: 0.0,
                rolled_angle: None,
            });
        }
        let nb = members.len();
        // Wheelsets numbered from the front (largest x) as in the logs.
        let order = v.wheelsets_from_front();
        let mut number = vec![0u32; order.len()];
        for (k, &i) in order.iter().enumerate() {
            number[i] = k as u32;
        }
        let mut wheels = Vec::new();
        let material =
            Material::new(STEEL_SHEAR_MODULUS, STEEL_POISSON).map_err(|e| SimError::Model {
                message: e.to_string(),
            })?;
        let options: ContactOptions = scene.contact;
        // Wheels with the same profiles and wheelset geometry share one pair, built once (the
        // profiles' splines and arc-length curves are most of the cost of a model: 85 % of a
        // modal analysis of the Manchester vehicle when each of its eight wheels built its own).
        type PairKey = (WheelProfile, f64, RailProfile, f64, f64, Friction, f64, f64);
        let mut built: Vec<(PairKey, WheelRailContact)> = Vec::new();
        for (i, w) in v.wheelsets().iter().enumerate() {
            let first_wheel = wheels.len();
            for side in [Side::Left, Side::Right] {
                let k = usize::from(side == Side::Right);
                let mut contacts = Vec::new();
                for section in scene.track.rail_sections() {
                    let friction = rail_friction(scene, section, k);
                    let key: PairKey = (
                        w.profiles[k].clone(),
                        w.running_circle_from_back,
                        section.profiles[k].clone(),
                        section.inclination,
                        section.gauge,
                        friction.clone(),
                        w.nominal_radius,
                        w.back_to_back,
                    );
                    contacts.push(match built.iter().find(|(q, _)| *q == key) {
                        Some((_, contact)) => contact.clone(),
                        None => {
                            let contact =
                                build_contact(w, k, side, section, friction, material, options)?;
                            built.push((key, contact.clone()));
                            contact
                        }
                    });
                }
                wheels.push(WheelModel {
                    member: MemberIx(nb + i),
                    wheelset_number: number[i],
                    side,
                    contacts,
                    rail: None,
                    out_of_roundness: w.out_of_roundness[k].clone(),
                });
            }
            members.push(MemberModel {
                name: w.name.clone(),
                kind: MemberKind::Wheelset {
                    first_wheel,
                    radius: w.nominal_radius,
                },
                mass: w.mass,
                inertia: w.inertia,
                inertia_inv: inverse(&w.inertia).ok_or_else(|| SimError::Model {
                    message: format!("wheelset '{}': inertia matrix is singular", w.name),
                })?,
                p0: w.position,
                pos: [None; 6],
                rate: [None; 6],
                torque: w.torque,
                // bodies come first among the members, in the vehicle's order
                torque_reaction: w.torque_reaction.map(|b| MemberIx(b.index())),
                rolling_radius: w.nominal_radius,
                rolled_angle: None,
            });
        }
        // State layout: positions, rates, internal states.
        let index = |m: Member| match m {
            Member::Body(b) => b.index(),
            Member::Wheelset(w) => nb + w.index(),
        };
        let mut state_names = Vec::new();
        let mut n_pos = 0;
        for d in &free {
            let m = &mut members[index(d.member)];
            if m.is_wheelset() && d.kind == DofKind::Pitch {
                continue;
            }
            m.pos[d.kind.index()] = Some(n_pos);
            state_names.push(v.dof_name(*d));
            n_pos += 1;
        }
        let mut n_rate = 0;
        for d in &free {
            members[index(d.member)].rate[d.kind.index()] = Some(n_pos + n_rate);
            state_names.push(format!("d/dt {}", v.dof_name(*d)));
            n_rate += 1;
        }
        let mut elements = Vec::new();
        let mut n_internal = 0;
        let end = |e: Endpoint| match e {
            Endpoint::Track => End::Track,
            Endpoint::Member(m) => End::Member(MemberIx(index(m))),
        };
        for f in v.forces() {
            let count = f.law.internal_states();
            let internal = (count > 0).then_some(n_pos + n_rate + n_internal);
            n_internal += count;
            match &f.law {
                ForceLaw::PlanarFriction { axes, .. } => {
                    for a in axes {
                        state_names.push(format!("{} friction slip {}", f.name, a.name()));
                    }
                }
                law if law.is_friction() => state_names.push(format!("{} friction slip", f.name)),
                _ if count > 0 => state_names.push(format!("{} damper elongation", f.name)),
                _ => {}
            }
            elements.push(ElementModel {
                name: f.name.clone(),
                ends: [end(f.body1), end(f.body2)],
                points: [f.point1, f.point2],
                axes: f.axes,
                law: f.law.clone(),
                line: f.line.then(|| f.nominal_length()),
                internal,
                preload: [0.0; 6],
            });
        }
        let is_friction = |e: &ElementModel| e.law.is_friction();
        let element_order: Vec<usize> = (0..elements.len())
            .filter(|&i| !is_friction(&elements[i]))
            .chain((0..elements.len()).filter(|&i| is_friction(&elements[i])))
            .collect();
        if elements.iter().any(|e| e.ends == [End::Track, End::Track]) {
            return Err(SimError::Model {
                message: "a force element joins the track to the track".into(),
            });
        }
        // Rail states: only on an elastic rail support.
        let rail_support = scene.track.rail_support().copied();
        let mut n_rail = 0;
        if rail_support.is_some() {
            let first = n_pos + n_rate + n_internal;
            for w in wheels.iter_mut() {
                w.rail = Some(first + n_rail);
                n_rail += 4;
                let name = format!("{} {} rail", members[w.member.0].name, w.side.name());
                for q in ["y", "z", "d/dt y", "d/dt z"] {
                    state_names.push(format!("{name} {q}"));
                }
            }
        }
        // Rolled-angle states: only for wheelsets with an out-of-round wheel.
        let mut n_angle = 0;
        for (mi, mm) in members.iter_mut().enumerate() {
            let defect = wheels
                .iter()
                .any(|w| w.member.0 == mi && !w.out_of_roundness.is_empty());
            if defect {
                mm.rolled_angle = Some(n_pos + n_rate + n_internal + n_rail + n_angle);
                n_angle += 1;
                state_names.push(format!("{} rolled angle lag", mm.name));
            }
        }
        Ok(SimModel {
            members,
            element_order,
            elements,
            wheels,
            track: scene.track.clone(),
            speed: scene.speed.clone(),
            start: scene.start,
            gravity: v.gravity(),
            cant_base: scene.track.cant_base(),
            warm_start: scene.warm_start,
            n_pos,
            n_rate,
            n_internal,
            rail_support,
            n_rail,
            n_angle,
            state_names,
            comfort: None,
            bogies: Vec::new(),
        }
        .with_comfort_points(v, &scene.assessment.comfort_points)
        .with_bogies(v))
    }

    /// `self` with [`SimModel::bogies`]: `v`'s ([`VehicleModel::bogies`]), each frame's mass
    /// with its wheelsets' and a measuring point above each of its wheelsets.
    fn with_bogies(mut self, v: &VehicleModel) -> SimModel {
        let nb = v.bodies().len();
        self.bogies = v
            .bogies()
            .iter()
            .map(|g| {
                let frame = &self.members[g.frame.index()];
                let wheelsets = g.wheelsets.iter().map(|w| &self.members[nb + w.index()]);
                BogieModel {
                    member: g.frame.index(),
                    mass: wheelsets.clone().fold(frame.mass, |sum, m| sum + m.mass),
                    points: wheelsets
                        .map(|m| {
                            (
                                format!("{} above {}", frame.name, m.name),
                                [m.p0[0] - frame.p0[0], 0.0, 0.0],
                            )
                        })
                        .collect(),
                }
            })
            .collect();
        self
    }

    /// `self` with [`SimModel::comfort`] resolved from the scene's points (`given`) on `v`'s
    /// carbody ([`VehicleModel::carbody`]); by default its centre and above every other body at
    /// least [`BOGIE_FRAME_MIN_OFFSET`] from it along x.
    fn with_comfort_points(mut self, v: &VehicleModel, given: &[ComfortPoint]) -> SimModel {
        let Some(cb) = v.carbody().map(|b| b.index()) else {
            return self;
        };
        let carbody = &self.members[cb];
        let points = if given.is_empty() {
            let mut points = vec![ComfortPoint {
                name: format!("{} centre", carbody.name),
                offset: [0.0; 3],
            }];
            // (rigid bodies are the first members, in the vehicle's order)
            for (i, b) in self.members[..v.bodies().len()].iter().enumerate() {
                let dx = b.p0[0] - carbody.p0[0];
                if i != cb && dx.abs() >= BOGIE_FRAME_MIN_OFFSET {
                    points.push(ComfortPoint {
                        name: format!("{} above {}", carbody.name, b.name),
                        offset: [dx, 0.0, 0.0],
                    });
                }
            }
            points
        } else {
            given.to_vec()
        };
        self.comfort = Some((cb, points));
        self
    }

    /// Length of the state vector.
    pub fn dim(&self) -> usize {
        self.n_pos + self.n_rate + self.n_internal + self.n_rail + self.n_angle
    }

    /// The displacement (y, z) of the rail under wheel `wi` and its rate (vy, vz) in state `x`,
    /// in the wheelset's track frame; zero on rigid rails.
    pub fn rail_state(&self, wi: usize, x: &[f64]) -> [f64; 4] {
        match self.wheels[wi].rail {
            Some(i) => [x[i], x[i + 1], x[i + 2], x[i + 3]],
            None => [0.0; 4],
        }
    }

    /// What an out-of-round wheel changes in its contact's input, for wheel `wi` at the
    /// wheelset's track position `s_wheel` with nominal radius `r0`, rolled-angle lag `lag`
    /// (`MemberModel::rolled_angle`, the integral of Ω − (V + ẋ)/r0 from the start; 0 where it
    /// has none) and velocity `vel`. The wheel rests on the lowest point of its rim
    /// ([`railsim_vehicle::rim_support`]): at the rolled angle θ = `s_wheel`/`r0` + `lag` its
    /// centre stands e(θ) higher than a round wheel's, e the rim's support function less r0
    /// (δr(θ) at the bottom of the wheel where the rim is round about it; on a defect's flank the
    /// lowest rim point lies ahead of or behind the bottom). This height:
    /// - is met as a vertical displacement of the rail, e up and de/dθ·Ω its rate (a larger
    ///   radius lifts the axle as a raised rail does; the rate is the vertical velocity of the
    ///   wheel's material point at the support): added to `rail` (the rail's own displacement
    ///   (y, z, vy, vz) \[m, m/s\], an elastic support's, [`SimModel::rail_state`]) and
    ///   returned, for [`crate::dynamics::rail_frame`];
    /// - puts the wheel's surface point at the contact e further below the axle and x_c ahead of
    ///   it (below), so its velocity differs from that of the point below the axle, where the
    ///   contact solves the patch, by ω × (x_c, 0, −e): it runs −Ω e more along the track (added
    ///   to `vel.vx`, which also divides the creepages: their relative change e/r0, 1e-4 for
    ///   0.05 mm, is left in that reference speed) and ω_z x_c + ω_x e more to the left (added to
    ///   `vel.vy`; since stop 38). Rigid-body kinematics of the wheel surface point
    ///   (contact-theory.md §3.1's creepage).
    ///
    /// Also returned: the support point's lead x_c = (r0 + δr(θ + u*)) sin u* = de/dθ \[m\] ahead
    /// of the axle (behind where negative), the lever of the contact's vertical force about the
    /// axle (the rim's tangent at its lowest point is level, so the normal stays vertical).
    ///
    /// A round wheel returns `rail`, no lead, and leaves `vel` as it is. Source: the out-of-round wheel as
    /// a moving irregularity of the wheel/rail gap, as in wheel-flat impact models (e.g. Wu &
    /// Thompson, J. Sound Vib. 251, 2002), with the wheel centre's geometric path over a flat
    /// rail; docs/models/dynamics.md, "Out-of-round wheels".
    pub fn wheel_support(
        &self,
        wi: usize,
        rail: [f64; 4],
        (s_wheel, r0, lag): (f64, f64, f64),
        vel: &mut WheelsetVelocity,
    ) -> ([f64; 4], f64) {
        let defects = &self.wheels[wi].out_of_roundness;
        if defects.is_empty() {
            return (rail, 0.0);
        }
        let (e, de) = rim_support(defects, s_wheel / r0 + lag, r0);
        // the wheel's material point at the support, (x_c, 0, -e) from the point below the
        // axle where the contact solves the patch: its velocity differs by ω × (x_c, 0, -e)
        // (the vertical part, -Ω x_c, is the rail's rate below)
        vel.vx -= vel.spin * e;
        vel.vy += vel.yaw_rate * de + vel.roll_rate * e;
        ([rail[0], rail[1] + e, rail[2], rail[3] + de * vel.spin], de)
    }

    /// \[s\] the times in `(t0, t_end)` at which the right-hand side is not smooth in time,
    /// for the integrator to end a step on each (`railsim_ode::Integrator::set_breakpoints`):
    /// where a member's nominal position (the reference point's plus its `p0`) reaches the
    /// start of a track segment (curvature, cant or their slopes change there); where a
    /// wheelset's reaches the start or the end of a rail section's transition (the contact
    /// forces' blend starts or ends, or the rails change at once); and where the speed
    /// profile has a point (the acceleration jumps). A member's own longitudinal motion
    /// (millimetres at most) moves its crossing by its distance over the speed, some tens of
    /// microseconds; the track irregularities, sampled finely, are not included.
    pub fn breakpoints(&self, t0: f64, t_end: f64) -> Vec<f64> {
        let mut out = Vec::new();
        let mut at = |distance: f64| {
            if distance > 0.0 {
                let t = self.speed.time_at(distance);
                if t > t0 && t < t_end {
                    out.push(t);
                }
            }
        };
        for &d in self.speed.distances().iter().skip(1) {
            at(d);
        }
        for m in &self.members {
            let offset = self.start + m.p0[0];
            for seg in self.track.segments().iter().skip(1) {
                at(seg.s_start - offset);
            }
            if matches!(m.kind, MemberKind::Wheelset { .. }) {
                for r in self.track.rail_sections().iter().skip(1) {
                    at(r.start - offset);
                    if r.transition > 0.0 {
                        at(r.start + r.transition - offset);
                    }
                }
            }
        }
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// \[m, m/s, m/s²\] distance run, speed and its time derivative at time `t`.
    pub fn motion(&self, t: f64) -> (f64, f64, f64) {
        let d = self.speed.distance_at(t);
        let v = self.speed.speed_at(d);
        let h = 0.01;
        let dv_dd = (self.speed.speed_at(d + h) - self.speed.speed_at((d - h).max(0.0)))
            / (d + h - (d - h).max(0.0));
        (d, v, v * dv_dd)
    }

    /// \[m\] member `m`'s track position in state `x` when the frame's reference point is at
    /// track position `s` \[m\]: `s` plus its initial and current x in the frame.
    pub fn track_x(&self, m: usize, s: f64, x: &[f64]) -> f64 {
        s + self.members[m].p0[0] + self.coord(m, 0, x)
    }

    /// A member's coordinate `k` (0..6) in state `x` (0 when frozen).
    pub fn coord(&self, m: usize, k: usize, x: &[f64]) -> f64 {
        self.members[m].pos[k].map_or(0.0, |i| x[i])
    }

    /// A member's rate `k` in state `x`; a frozen wheelset spin rolls at `v / r`, r its
    /// initial rolling radius.
    pub fn coord_rate(&self, m: usize, k: usize, x: &[f64], v: f64) -> f64 {
        let mm = &self.members[m];
        match (mm.rate[k], mm.kind) {
            (Some(i), _) => x[i],
            (None, MemberKind::Wheelset { .. }) if k == 4 => v / mm.rolling_radius,
            (None, _) => 0.0,
        }
    }

    /// The structure of the right-hand side's Jacobian ([`railsim_ode::JacobianPattern`]),
    /// from the model's topology: a member's derivatives depend on its own states and on
    /// those of every member, element state and rail it is coupled to. The couplings, each
    /// taken in both directions (a superset of the true dependences, which is safe):
    /// - a force element couples its end members and its internal states; a friction element
    ///   also the ends and states of its normal-load element;
    /// - a wheel couples its wheelset (with its rolled angle, where it has one) and the states
    ///   of the rail mass under it (its contact force depends on both and acts on both);
    /// - a wheelset's traction torque couples it to the body that takes the reaction (the
    ///   axle's direction follows the wheelset's position along the track).
    ///
    /// Nothing else couples members: each follows the track at its own position, and the
    /// speed and the track depend on time only. A dependence missing here would make the
    /// grouped Jacobians wrong; `tests/jacobian_pattern.rs` compares them with the
    /// column-by-column difference on the scenes that use each coupling.
    pub fn jacobian_pattern(&self) -> railsim_ode::JacobianPattern {
        let n = self.dim();
        // the state indices of each block: members, then elements, then wheels' rails
        let mut blocks: Vec<Vec<usize>> = self
            .members
            .iter()
            .map(|mm| {
                mm.pos
                    .iter()
                    .chain(mm.rate.iter())
                    .chain(std::iter::once(&mm.rolled_angle))
                    .flatten()
                    .copied()
                    .collect()
            })
            .collect();
        let element_block = blocks.len();
        for el in &self.elements {
            let k = el.law.internal_states();
            blocks.push(el.internal.map_or(Vec::new(), |i| (i..i + k).collect()));
        }
        let rail_block = blocks.len();
        for w in &self.wheels {
            blocks.push(w.rail.map_or(Vec::new(), |i| (i..i + 4).collect()));
        }
        fn ends(el: &ElementModel) -> impl Iterator<Item = usize> + '_ {
            el.ends.iter().filter_map(|e| match e {
                End::Member(MemberIx(m)) => Some(*m),
                End::Track => None,
            })
        }
        let mut couplings: Vec<Vec<usize>> = (0..self.members.len()).map(|m| vec![m]).collect();
        for (ei, el) in self.elements.iter().enumerate() {
            let mut c: Vec<usize> = ends(el).collect();
            c.push(element_block + ei);
            if let ForceLaw::Friction {
                normal: Some(j), ..
            }
            | ForceLaw::PlanarFriction {
                normal: Some(j), ..
            } = &el.law
            {
                c.extend(ends(&self.elements[j.element.index()]));
                c.push(element_block + j.element.index());
            }
            couplings.push(c);
        }
        for (wi, w) in self.wheels.iter().enumerate() {
            couplings.push(vec![w.member.0, rail_block + wi]);
        }
        for (m, mm) in self.members.iter().enumerate() {
            if let Some(MemberIx(b)) = mm.torque_reaction {
                couplings.push(vec![m, b]);
            }
        }
        let mut pattern = railsim_ode::JacobianPattern::new(n);
        for c in &couplings {
            for &rb in c {
                for &cb in c {
                    for &row in &blocks[rb] {
                        for &col in &blocks[cb] {
                            pattern
                                .insert(row, col)
                                .expect("state indices are below the model's dimension");
                        }
                    }
                }
            }
        }
        pattern
    }

    /// The wheelsets' names (the vehicle file's) in the order of their numbers, from the front
    /// (the order of the logs' `/wheelsets/N` topics and of the run summary).
    pub fn wheelset_names(&self) -> Vec<String> {
        let mut named: Vec<(u32, &str)> = self
            .wheels
            .chunks(2)
            .map(|pair| {
                let w = &pair[0];
                (w.wheelset_number, self.members[w.member.0].name.as_str())
            })
            .collect();
        named.sort_by_key(|&(n, _)| n);
        named.into_iter().map(|(_, name)| name.to_owned()).collect()
    }

    /// The contact pose of a wheelset's axle relative to the local track (no irregularity).
    pub fn wheelset_pose(&self, m: usize, x: &[f64]) -> WheelsetPose {
        let mm = &self.members[m];
        let radius = match mm.kind {
            MemberKind::Wheelset { radius, .. } => radius,
            MemberKind::Body => 0.0,
        };
        WheelsetPose {
            y: mm.p0[1] + self.coord(m, 1, x),
            z: mm.p0[2] + self.coord(m, 2, x) - radius,
            roll: self.coord(m, 3, x),
            yaw: self.coord(m, 5, x),
        }
    }
}

/// The friction on rail `k` (0 left, 1 right) of a rail `section`: the section's, or the
/// scene's where the section sets none.
fn rail_friction(scene: &Scene, section: &RailSection, k: usize) -> Friction {
    section
        .friction
        .as_ref()
        .map_or_else(|| scene.friction[k].clone(), |f| friction_model(f, k))
}

/// The contact pair of wheel `k` (0 left, 1 right) of wheelset `w`: its wheel profile on the
/// rail profile of the track's rail `section` with `friction` (`rail_friction`), evaluated with
/// the scene's contact `options`.
fn build_contact(
    w: &Wheelset,
    k: usize,
    side: Side,
    section: &RailSection,
    friction: Friction,
    material: Material,
    options: ContactOptions,
) -> Result<WheelRailContact, SimError> {
    // (the profile's own error names its file and line; the key that names the file is added)
    let wheel =
        wheel_profile(&w.profiles[k], w.running_circle_from_back).map_err(|e| SimError::Model {
            message: format!(
                "wheelset '{}', {} wheel_profile (vehicle file): {e}",
                w.name,
                side.name()
            ),
        })?;
    let rail = rail_profile(&section.profiles[k]).map_err(|e| SimError::Model {
        message: format!("{} rail_profile (track file): {e}", side.name()),
    })?;
    let inclination = section.inclination;
    let pair = WheelRailPair::new(&PairSpec {
        wheel,
        rail,
        r0: w.nominal_radius,
        flange_back_distance: w.back_to_back,
        flange_back_y: -w.running_circle_from_back,
        gauge: section.gauge,
        gauge_depth: 0.014,
        inclination,
        material,
        friction,
        curve_ds: 5e-5,
        smoothing: 0.0,
    })
    .map_err(|e| SimError::Model {
        message: format!("wheelset '{}', {} wheel: {e}", w.name, side.name()),
    })?;
    WheelRailContact::new(pair, options).map_err(|e| SimError::Model {
        message: format!("wheelset '{}': {e}", w.name),
    })
}

fn wheel_profile(p: &WheelProfile, running_circle_from_back: f64) -> Result<Profile, ProfileError> {
    match p {
        WheelProfile::S1002 => Ok(analytic::s1002()),
        WheelProfile::Cone { conicity } => cone(*conicity, running_circle_from_back),
        WheelProfile::File(path) => read_profile(path, ProfileKind::Wheel),
    }
}

/// A pure cone through the running circle: radius r0 − λ·y from the flange back to 60 mm on the
/// field side, no flange (Klingel and Wickens checks).
fn cone(conicity: f64, running_circle_from_back: f64) -> Result<Profile, ProfileError> {
    let y0 = -running_circle_from_back + 0.005;
    let n = ((0.06 - y0) / 0.0005).ceil() as usize;
    let points: Vec<[f64; 2]> = (0..=n)
        .map(|i| {
            let y = y0 + i as f64 * 0.0005;
            [y, conicity * y]
        })
        .collect();
    Profile::new(format!("cone:{conicity}"), ProfileKind::Wheel, points)
}

fn rail_profile(p: &RailProfile) -> Result<Profile, ProfileError> {
    match p {
        RailProfile::Uic60 => Ok(analytic::uic60()),
        RailProfile::File(path) => read_profile(path, ProfileKind::Rail),
    }
}

/// SIMPACK `.prw`/`.prr` files by extension, else a y–z table in mm.
fn read_profile(path: &std::path::Path, kind: ProfileKind) -> Result<Profile, ProfileError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("prw" | "prr") => read_simpack(path, kind),
        _ => read_table_mm(path, kind),
    }
}
