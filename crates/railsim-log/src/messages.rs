//! Message types written to and read from railsim logs.
//!
//! Every message is encoded as JSON (`json` message encoding) and described by a JSON Schema
//! (`jsonschema` schema encoding). The railsim types derive their schema with `schemars`; the
//! Foxglove [`FrameTransform`] uses Foxglove's published schema, embedded from
//! `schemas/foxglove.FrameTransform.json`.
//!
//! Units are SI. A field whose doc starts with a unit in brackets carries that unit into the
//! schema's `description`, and the CSV export reads it back from there for its column headers.
//! Positions, velocities and forces are in the track frame T of `docs/conventions.md` (x along the
//! track, y to the left, z up) unless a field says otherwise.

use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// A message type that can be logged: it knows its schema name and JSON Schema.
pub trait LogMessage: Serialize + DeserializeOwned {
    /// The MCAP schema name, e.g. `railsim.BodyState` or `foxglove.FrameTransform`.
    const SCHEMA_NAME: &'static str;
    /// The JSON Schema of the message, as bytes of JSON text. Must be deterministic.
    fn schema_json() -> Vec<u8>;
}

fn generated_schema<T: JsonSchema>() -> Vec<u8> {
    let mut schema: serde_json::Value = schemars::schema_for!(T).into();
    unescape_units(&mut schema);
    // Serialising a JSON value cannot fail: it has string keys only.
    serde_json::to_vec_pretty(&schema).unwrap_or_default()
}

/// The doc comments escape unit brackets for rustdoc (`\[m\]`); schema readers should see `[m]`.
fn unescape_units(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::String(s) if s.contains('\\') => {
            *s = s.replace("\\[", "[").replace("\\]", "]");
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(unescape_units),
        serde_json::Value::Object(map) => map.values_mut().for_each(unescape_units),
        _ => {}
    }
}

/// A rotation as a unit quaternion (Hamilton convention, scalar last as Foxglove writes it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Quaternion {
    /// \[1\] x component of the vector part
    pub x: f64,
    /// \[1\] y component of the vector part
    pub y: f64,
    /// \[1\] z component of the vector part
    pub z: f64,
    /// \[1\] scalar part
    pub w: f64,
}

impl Quaternion {
    /// The identity rotation.
    pub const IDENTITY: Quaternion = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };
}

/// The state of one rigid body: pose and velocities of its reference point (centre of gravity).
///
/// Topic `/bodies/<name>`, schema `railsim.BodyState`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodyState {
    /// \[s\] simulation time (equal to the message's log time, as a convenience for plots)
    pub t_s: f64,
    /// Body name as in the vehicle model.
    pub name: String,
    /// \[m\] position of the body reference point: its nominal position in the vehicle plus its
    /// coordinates in its own track-following frame T (x along the track, so not the distance s)
    pub position: [f64; 3],
    /// \[1\] orientation of the body frame relative to its track-following frame T (a
    /// wheelset's axle frame, without the spin angle)
    pub orientation: Quaternion,
    /// \[m/s\] absolute velocity of the body reference point, components in T
    pub velocity: [f64; 3],
    /// \[rad/s\] absolute angular velocity of the body, components in T (a wheelset's with
    /// its spin about the axle)
    pub angular_velocity: [f64; 3],
}

impl LogMessage for BodyState {
    const SCHEMA_NAME: &'static str = "railsim.BodyState";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// Which wheel of a wheelset.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// The left wheel (track y > 0).
    Left,
    /// The right wheel (track y < 0).
    Right,
}

impl Side {
    /// `"left"` or `"right"`, as used in topic names and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// Kalker's creepages of one contact patch, in the patch axes (see `docs/conventions.md`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Creepages {
    /// \[1\] longitudinal creepage ξ
    pub xi: f64,
    /// \[1\] lateral creepage η (along the patch s axis)
    pub eta: f64,
    /// \[1/m\] spin creepage φ
    pub phi_per_m: f64,
}

/// The result of one wheel–rail contact patch at one instant.
///
/// Topic `/contact/<wheelset>/<side>` (all patches of that wheel, told apart by `patch`), schema
/// `railsim.PatchMessage`. Forces and moments are on the wheel, in the patch axes, with the signs
/// of `docs/conventions.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PatchMessage {
    /// \[s\] simulation time
    pub t_s: f64,
    /// Wheelset index, counted from the front of the vehicle from 0.
    pub wheelset: u32,
    /// Which wheel.
    pub side: Side,
    /// Patch index on this wheel, from 0 (ordered toward the flange).
    pub patch: u32,
    /// \[m\] lateral position of the patch reference point on the rail profile (toward the field side)
    pub y_rail_m: f64,
    /// \[m\] lateral position of the patch reference point on the wheel profile (toward the field side)
    pub y_wheel_m: f64,
    /// \[rad\] contact angle, positive when the normal leans toward the flange
    pub contact_angle_rad: f64,
    /// \[m\] virtual penetration (maximum interpenetration of the undeformed profiles)
    pub penetration_m: f64,
    /// Kalker's creepages ξ, η, φ.
    pub creepages: Creepages,
    /// \[N\] normal force, positive in compression
    pub fn_n: f64,
    /// \[N\] longitudinal creep force on the wheel
    pub fx_n: f64,
    /// \[N\] lateral creep force on the wheel (patch s axis)
    pub fy_n: f64,
    /// \[N m\] spin moment on the wheel about the patch normal
    pub mz_nm: f64,
    /// \[N\] wear number Tγ, see [`wear_number`]
    pub wear_number_n: f64,
    /// \[-\] in a rail transition, the share the wheel carries of this patch (on one of the
    /// two rails it passes between): the forces and the wear number above are that share;
    /// absent elsewhere (a share of 1)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weight: Option<f64>,
}

impl LogMessage for PatchMessage {
    const SCHEMA_NAME: &'static str = "railsim.PatchMessage";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// \[N\] The wear number Tγ of a patch: the frictional work per unit rolled distance.
///
/// Tγ = Fx ξ + Fy η, with the creep forces taken **on the rail** (Pearce & Sherratt's
/// convention, in which forces and creepages have the same sign, so Tγ ≥ 0 without spin).
/// railsim's forces are on the wheel and oppose the creepage, so this function returns
/// −(fx ξ + fy η) for wheel forces. The spin term (Mz φ) is neglected, as in the original
/// wear-number model; with spin, Fy also carries a part due to spin, so where η is small the sum
/// can be slightly negative (−0.2 N on a trailing wheelset of the Manchester vehicle at
/// R = 1200 m, against 50 N on the leading one).
///
/// Reference: T. G. Pearce and N. D. Sherratt, "Prediction of wheel profile wear", *Wear* 144
/// (1991) 343–351.
pub fn wear_number(fx_on_wheel_n: f64, fy_on_wheel_n: f64, creepages: &Creepages) -> f64 {
    -(fx_on_wheel_n * creepages.xi + fy_on_wheel_n * creepages.eta)
}

/// Per-wheelset running-safety quantities at one instant.
///
/// Topic `/wheelsets/<n>`, schema `railsim.WheelsetMessage`. Y is the lateral force of the
/// wheel on the rail, positive toward that rail's field side (a flange contact gives Y > 0); Q is
/// the vertical force of the wheel on the rail, positive downward. Both are summed over the
/// wheel's patches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WheelsetMessage {
    /// \[s\] simulation time
    pub t_s: f64,
    /// Wheelset index, counted from the front of the vehicle from 0.
    pub wheelset: u32,
    /// \[N\] lateral force Y of the left wheel on the rail, positive toward the field side
    pub y_left_n: f64,
    /// \[N\] vertical force Q of the left wheel on the rail, positive downward
    pub q_left_n: f64,
    /// \[N\] lateral force Y of the right wheel on the rail, positive toward the field side
    pub y_right_n: f64,
    /// \[N\] vertical force Q of the right wheel on the rail, positive downward
    pub q_right_n: f64,
    /// \[1\] derailment quotient Y/Q of the left wheel
    pub y_over_q_left: f64,
    /// \[1\] derailment quotient Y/Q of the right wheel
    pub y_over_q_right: f64,
    /// \[rad\] angle of attack: wheelset yaw relative to the track, positive nose-left
    pub angle_of_attack_rad: f64,
    /// \[N\] wear number Tγ of the left wheel: the sum over its patches (as on `/contact`);
    /// 0 in logs written before it was added
    #[serde(default)]
    pub wear_number_left_n: f64,
    /// \[N\] wear number Tγ of the right wheel, likewise
    #[serde(default)]
    pub wear_number_right_n: f64,
    /// \[m\] on an elastic rail support only: displacement of the rail under each wheel,
    /// track frame, `[left y, left z, right y, right z]` (y to the left, z up)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rail_displacement_m: Option<[f64; 4]>,
}

impl LogMessage for WheelsetMessage {
    const SCHEMA_NAME: &'static str = "railsim.WheelsetMessage";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// What an accelerometer fixed to the carbody at one point measures at one instant.
///
/// Topic `/carbody/<n>` (points numbered from 0: the carbody's centre, then above each bogie),
/// schema `railsim.CarbodyMessage`: the specific force (acceleration minus gravity) in the
/// carbody's axes; at rest on level track (0, 0, +9.81).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CarbodyMessage {
    /// \[s\] simulation time
    pub t_s: f64,
    /// Name of the point, e.g. `carbody above bogie_front`.
    pub point: String,
    /// \[m/s^2\] longitudinal specific force, carbody x (forward)
    pub longitudinal_m_s2: f64,
    /// \[m/s^2\] lateral specific force, carbody y (to the left)
    pub lateral_m_s2: f64,
    /// \[m/s^2\] vertical specific force, carbody z (up)
    pub vertical_m_s2: f64,
}

impl LogMessage for CarbodyMessage {
    const SCHEMA_NAME: &'static str = "railsim.CarbodyMessage";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// What a lateral accelerometer fixed to a bogie frame above one of its wheelsets measures at
/// one instant (EN 14363's simplified stability method).
///
/// Topic `/bogie_frames/<n>` (points numbered from 0 over all frames, front first, each frame's
/// wheelsets front first, as in the run summary), schema `railsim.BogieFrameMessage`: the
/// specific force (acceleration minus gravity) in the frame's axes; at rest on level track
/// (0, 0, +9.81).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BogieFrameMessage {
    /// \[s\] simulation time
    pub t_s: f64,
    /// Name of the point, e.g. `bogie_front above ws1`.
    pub point: String,
    /// \[m/s^2\] longitudinal specific force, frame x (forward)
    pub longitudinal_m_s2: f64,
    /// \[m/s^2\] lateral specific force, frame y (to the left)
    pub lateral_m_s2: f64,
    /// \[m/s^2\] vertical specific force, frame z (up)
    pub vertical_m_s2: f64,
}

impl LogMessage for BogieFrameMessage {
    const SCHEMA_NAME: &'static str = "railsim.BogieFrameMessage";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// One suspension force element at one instant: its deflections, rates and forces in its own
/// local axes, and its internal state.
///
/// Topic `/elements/<name>`, schema `railsim.ElementMessage`. Deflections are body 2's
/// attachment point relative to body 1's from the nominal configuration, rotations body 2's
/// relative to body 1's; forces and moments act on body 2 (body 1 receives the opposite).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElementMessage {
    /// \[s\] simulation time
    pub t_s: f64,
    /// The element's name.
    pub element: String,
    /// Its type as written in the vehicle file, e.g. `friction`.
    #[serde(rename = "type")]
    pub kind: String,
    /// \[m\] deflection along the local x, y, z axes
    pub deflection_m: [f64; 3],
    /// \[m/s\] its rate
    pub deflection_rate_m_s: [f64; 3],
    /// \[rad\] rotation about the local axes (small angles)
    pub rotation_rad: [f64; 3],
    /// \[N\] force on body 2 along the local axes
    pub force_n: [f64; 3],
    /// \[N m\] moment on body 2 about the local axes
    pub moment_nm: [f64; 3],
    /// \[m\] the internal states, if the element has any: a damper's elongation or a friction
    /// slider's position (as deflections: the element is relaxed where they equal the
    /// deflection; \[rad\] for a rotational friction, compared with the rotation; two values,
    /// along the plane's two axes, for a planar friction)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_m: Option<Vec<f64>>,
    /// \[N\] a friction element's sliding force at this instant (its constant part plus its
    /// coefficient times the normal element's force)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sliding_force_n: Option<f64>,
    /// \[N m\] a rotational friction element's sliding moment at this instant
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sliding_moment_nm: Option<f64>,
    /// \[W\] power the element absorbs from the bodies at this instant, −(F·Δ̇ + M·ω)
    #[serde(default)]
    pub power_w: f64,
    /// \[W\] the part of `power_w` it dissipates (never negative; 0 for springs, tables and
    /// anti-roll bars)
    #[serde(default)]
    pub dissipation_w: f64,
    /// \[J\] work it has absorbed since the first sample (trapezoidal rule over the run's
    /// samples, which may be more than the log holds: the scene metadata's
    /// `assessment_rate_hz`)
    #[serde(default)]
    pub work_j: f64,
    /// \[J\] energy it has dissipated since the first sample (likewise)
    #[serde(default)]
    pub dissipated_j: f64,
}

impl LogMessage for ElementMessage {
    const SCHEMA_NAME: &'static str = "railsim.ElementMessage";
    fn schema_json() -> Vec<u8> {
        generated_schema::<Self>()
    }
}

/// A time as Foxglove writes it: whole seconds and nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct FoxgloveTime {
    /// \[s\] whole seconds
    pub sec: u64,
    /// \[ns\] nanoseconds, 0 ..= 999 999 999
    pub nsec: u32,
}

impl FoxgloveTime {
    /// Splits integer nanoseconds into seconds and nanoseconds.
    pub fn from_ns(t_ns: u64) -> Self {
        FoxgloveTime {
            sec: t_ns / 1_000_000_000,
            // The remainder is below 1e9, so it fits in u32.
            nsec: (t_ns % 1_000_000_000) as u32,
        }
    }

    /// \[ns\] The time as integer nanoseconds (saturating).
    pub fn to_ns(self) -> u64 {
        self.sec
            .saturating_mul(1_000_000_000)
            .saturating_add(u64::from(self.nsec))
    }
}

/// A vector with named components, as in Foxglove's `foxglove.Vector3`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x component
    pub x: f64,
    /// y component
    pub y: f64,
    /// z component
    pub z: f64,
}

/// Foxglove's `foxglove.FrameTransform`: the pose of `child_frame_id` in `parent_frame_id`.
///
/// Topic `/tf`, schema name exactly `foxglove.FrameTransform` with Foxglove's own JSON Schema, so
/// that Foxglove's 3D panel moves the frames. railsim uses the parent frame `track` (the track
/// frame T) and one child frame per body, named as the body; translation in \[m\].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameTransform {
    /// Time of the transform; railsim sets it to the message's log time.
    pub timestamp: FoxgloveTime,
    /// Name of the parent frame.
    pub parent_frame_id: String,
    /// Name of the child frame.
    pub child_frame_id: String,
    /// \[m\] position of the child frame's origin in the parent frame
    pub translation: Vector3,
    /// \[1\] orientation of the child frame in the parent frame
    pub rotation: Quaternion,
}

/// Foxglove's JSON Schema of `foxglove.FrameTransform` (MIT, see `schemas/SOURCE.md`).
pub const FRAME_TRANSFORM_SCHEMA: &str = include_str!("../schemas/foxglove.FrameTransform.json");

impl LogMessage for FrameTransform {
    const SCHEMA_NAME: &'static str = "foxglove.FrameTransform";
    fn schema_json() -> Vec<u8> {
        FRAME_TRANSFORM_SCHEMA.as_bytes().to_vec()
    }
}

impl FrameTransform {
    /// The transform of a body's frame in the track frame, stamped with `t_ns`.
    pub fn from_body(t_ns: u64, parent_frame_id: &str, body: &BodyState) -> Self {
        FrameTransform {
            timestamp: FoxgloveTime::from_ns(t_ns),
            parent_frame_id: parent_frame_id.to_owned(),
            child_frame_id: body.name.clone(),
            translation: Vector3 {
                x: body.position[0],
                y: body.position[1],
                z: body.position[2],
            },
            rotation: body.orientation,
        }
    }
}

/// Topic names used by railsim.
pub mod topics {
    use super::Side;

    /// The topic of Foxglove frame transforms.
    pub const TF: &str = "/tf";

    /// `/bodies/<name>`.
    pub fn body(name: &str) -> String {
        format!("/bodies/{name}")
    }

    /// `/contact/<wheelset>/<side>`.
    pub fn contact(wheelset: u32, side: Side) -> String {
        format!("/contact/{wheelset}/{}", side.as_str())
    }

    /// `/wheelsets/<n>`.
    pub fn wheelset(wheelset: u32) -> String {
        format!("/wheelsets/{wheelset}")
    }

    /// `/carbody/<n>`.
    pub fn carbody(point: usize) -> String {
        format!("/carbody/{point}")
    }

    /// `/bogie_frames/<n>`.
    pub fn bogie_frame(point: usize) -> String {
        format!("/bogie_frames/{point}")
    }

    /// `/elements/<name>`.
    pub fn element(name: &str) -> String {
        format!("/elements/{name}")
    }
}
