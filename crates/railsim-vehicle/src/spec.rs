//! `VehicleSpec`: the vehicle file as written, one to one with the TOML, in the file's units.
//!
//! Every value keeps its span so that [`crate::VehicleModel::compile`] can report
//! `file:line:col`. Unknown keys are rejected (`deny_unknown_fields`, and a check of every
//! table's keys before serde runs so that all unknown keys are reported, with a suggestion).
//! The format is documented in `docs/formats/vehicle.md`.
//!
//! Keys are optional at the serde level; which ones are required is checked by the compile
//! step, so that every missing key of every element is reported in one run. The reader parses
//! the root table and each `[[body]]`, `[[wheelset]]` and `[[force]]` separately; a value of the
//! wrong type is reported, dropped, and the table is read again, so one wrong type does not hide
//! the next one.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use railsim_spec::{as_is, read_table};

use crate::error::{Problem, Sink, SourceMap, VehicleError};

/// A whole vehicle file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// Free-text name of the vehicle.
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// Free-text description (sources, remarks).
    #[serde(default)]
    pub description: Option<Spanned<String>>,
    /// \[m/s²\] gravitational acceleration; default 9.81.
    #[serde(default)]
    pub gravity_m_per_s2: Option<Spanned<f64>>,
    /// Rigid bodies other than wheelsets (carbody, bogie frames, ...).
    #[serde(default)]
    pub body: Vec<Spanned<BodySpec>>,
    /// Wheelsets (at least one).
    #[serde(default)]
    pub wheelset: Vec<Spanned<WheelsetSpec>>,
    /// Force elements (suspension) between two bodies, or a body and the frame `"track"`.
    #[serde(default)]
    pub force: Vec<Spanned<ForceSpec>>,
    /// Names of elements that could not be read at all (their problems are already reported);
    /// references to them are not reported again.
    #[serde(skip)]
    pub unreadable_names: Vec<String>,
    /// Keys dropped by the reader because their value had the wrong type, per element:
    /// `(table span start, key)`. The compile step does not report them as missing.
    #[serde(skip)]
    pub dropped_keys: Vec<(usize, String)>,
    /// Line index of the text this spec was read from (empty when built in code).
    #[serde(skip)]
    pub source: SourceMap,
}

/// A rigid body (`[[body]]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Unique name among bodies and wheelsets (required).
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// \[kg\] mass (required, 1 to 1e6).
    #[serde(default)]
    pub mass_kg: Option<Spanned<f64>>,
    /// \[kg·m²\] moments of inertia `[Ixx, Iyy, Izz]` about the centre of gravity, vehicle axes
    /// (required).
    #[serde(default, deserialize_with = "three_numbers")]
    pub inertia_kgm2: Option<Spanned<[f64; 3]>>,
    /// \[kg·m²\] off-diagonal entries `[Ixy, Ixz, Iyz]` of the inertia tensor (the tensor's own
    /// entries, i.e. `Ixy = -∫xy dm`); default zero.
    #[serde(default, deserialize_with = "three_numbers")]
    pub products_kgm2: Option<Spanned<[f64; 3]>>,
    /// \[m\] centre of gravity `[x, y, z]` in the vehicle reference frame (required).
    #[serde(default, deserialize_with = "three_numbers")]
    pub position_m: Option<Spanned<[f64; 3]>>,
    /// Degrees of freedom held at their nominal value: any of `x y z roll pitch yaw`.
    #[serde(default)]
    pub frozen: Option<Spanned<Vec<Spanned<String>>>>,
}

/// A wheelset (`[[wheelset]]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetSpec {
    /// Unique name among bodies and wheelsets (required).
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// \[kg\] mass (required, > 0).
    #[serde(default)]
    pub mass_kg: Option<Spanned<f64>>,
    /// \[kg·m²\] `[Ixx, Iyy (spin), Izz]` about the centre of gravity (required).
    #[serde(default, deserialize_with = "three_numbers")]
    pub inertia_kgm2: Option<Spanned<[f64; 3]>>,
    /// \[kg·m²\] off-diagonal entries `[Ixy, Ixz, Iyz]`; default zero.
    #[serde(default, deserialize_with = "three_numbers")]
    pub products_kgm2: Option<Spanned<[f64; 3]>>,
    /// \[m\] axle centre `[x, y, z]` in the vehicle frame; z must equal the nominal radius
    /// (required).
    #[serde(default, deserialize_with = "three_numbers")]
    pub position_m: Option<Spanned<[f64; 3]>>,
    /// \[m\] nominal rolling radius r0 (required, > 0).
    #[serde(default)]
    pub nominal_radius_m: Option<Spanned<f64>>,
    /// \[mm\] flange-back (back-to-back) distance between the inner faces of the wheels
    /// (required; 1360 for standard gauge).
    #[serde(default)]
    pub back_to_back_mm: Option<Spanned<f64>>,
    /// \[mm\] distance from the wheel's back face to its running (measuring) circle; default 70.
    #[serde(default)]
    pub running_circle_from_back_mm: Option<Spanned<f64>>,
    /// Wheel profile per side (required).
    #[serde(default)]
    pub wheel_profile: Option<Spanned<WheelProfileSpec>>,
    /// \[N·m\] constant traction (> 0) or brake (< 0) torque about the axle; default 0.
    #[serde(default)]
    pub torque_nm: Option<Spanned<f64>>,
    /// The body that carries the torque's reaction (a bogie frame or the carbody); default:
    /// none modelled.
    #[serde(default)]
    pub torque_reaction: Option<Spanned<String>>,
    /// Degrees of freedom held at their nominal value: any of `x y z roll yaw spin`.
    #[serde(default)]
    pub frozen: Option<Spanned<Vec<Spanned<String>>>>,
    /// The wheels' out-of-roundness (`[[wheelset.out_of_roundness]]`): harmonics of the radius
    /// (polygonal wheels) and rounded flats; default none.
    #[serde(default)]
    pub out_of_roundness: Option<Spanned<Vec<Spanned<OutOfRoundnessSpec>>>>,
}

/// One out-of-roundness of a wheel (`[[wheelset.out_of_roundness]]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutOfRoundnessSpec {
    /// `"harmonic"` (a polygonal wheel) or `"flat"` (a rounded wheel flat) (required).
    #[serde(default, rename = "type")]
    pub kind: Option<Spanned<String>>,
    /// `"left"`, `"right"` or `"both"` (required).
    #[serde(default)]
    pub side: Option<Spanned<String>>,
    /// Harmonic: its order, the number of waves round the wheel, 1 to 100 (required).
    #[serde(default)]
    pub order: Option<Spanned<f64>>,
    /// \[mm\] harmonic: amplitude of the radius deviation, in (0, 5] (required).
    #[serde(default)]
    pub amplitude_mm: Option<Spanned<f64>>,
    /// \[deg\] harmonic: phase; default 0.
    #[serde(default)]
    pub phase_deg: Option<Spanned<f64>>,
    /// \[mm\] flat: length along the circumference, in (0, 300] (required).
    #[serde(default)]
    pub length_mm: Option<Spanned<f64>>,
    /// \[mm\] flat: depth, in (0, 5] (required).
    #[serde(default)]
    pub depth_mm: Option<Spanned<f64>>,
    /// \[deg\] flat: rolled angle at which its centre is at the bottom; default 0.
    #[serde(default)]
    pub position_deg: Option<Spanned<f64>>,
}

/// Wheel profile per side: the built-in name `"s1002"` or a file path relative to the vehicle
/// file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelProfileSpec {
    /// Profile of the left wheel.
    pub left: Spanned<String>,
    /// Profile of the right wheel.
    pub right: Spanned<String>,
}

/// A force element (`[[force]]`). Which keys apply depends on `type`; see
/// `docs/formats/vehicle.md`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSpec {
    /// Unique name among force elements (required).
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// `"bushing"`, `"table"`, `"series_spring_damper"`, `"damper"`, `"friction"`,
    /// `"planar_friction"`, `"rotational_friction"` or `"anti_roll_bar"` (required).
    #[serde(default, rename = "type")]
    pub kind: Option<Spanned<String>>,
    /// First body (a body or wheelset name, or `"track"`) (required).
    #[serde(default)]
    pub body1: Option<Spanned<String>>,
    /// Second body (a body or wheelset name, or `"track"`) (required).
    #[serde(default)]
    pub body2: Option<Spanned<String>>,
    /// \[m\] attachment point in the vehicle frame, nominal configuration; on both bodies unless
    /// `point2_m` is given (required).
    #[serde(default, deserialize_with = "three_numbers")]
    pub point_m: Option<Spanned<[f64; 3]>>,
    /// \[m\] attachment point on `body2` when it differs from `point_m` (e.g. a damper's ends).
    #[serde(default, deserialize_with = "three_numbers")]
    pub point2_m: Option<Spanned<[f64; 3]>>,
    /// \[deg\] orientation `[roll, pitch, yaw]` of the element's local axes relative to the
    /// vehicle axes (R = Rz(yaw)·Ry(pitch)·Rx(roll)); default zero.
    #[serde(default, deserialize_with = "three_numbers")]
    pub orientation_deg: Option<Spanned<[f64; 3]>>,
    /// Local axis a `table`, `series_spring_damper`, `damper` or `friction` acts along: `"x"`, `"y"`
    /// or `"z"`.
    #[serde(default)]
    pub direction: Option<Spanned<String>>,
    /// \[N/m\] bushing: `[kx, ky, kz]`; series spring-damper: the series spring, one number; damper:
    /// the optional mount stiffness in series; friction: the stick stiffness.
    #[serde(default)]
    pub stiffness_n_per_m: Option<Spanned<NumberOrTriple>>,
    /// \[N·s/m\] bushing: `[cx, cy, cz]`; series spring-damper: the damper, one number
    /// (docs/formats/vehicle.md lists every element's keys).
    #[serde(default)]
    pub damping_ns_per_m: Option<Spanned<NumberOrTriple>>,
    /// \[N·m/rad\] bushing: `[krx, kry, krz]`; anti-roll bar: one number (about x).
    #[serde(default)]
    pub rotational_stiffness_nm_per_rad: Option<Spanned<NumberOrTriple>>,
    /// \[N·m·s/rad\] bushing: `[crx, cry, crz]`.
    #[serde(default)]
    pub rotational_damping_nms_per_rad: Option<Spanned<NumberOrTriple>>,
    /// \[mm\] table: deflections, strictly increasing.
    #[serde(default)]
    pub deflection_mm: Option<Spanned<Vec<Spanned<f64>>>>,
    /// \[N\] table: restoring force magnitude at each deflection.
    #[serde(default)]
    pub force_n: Option<Spanned<Vec<Spanned<f64>>>>,
    /// Table: mirror the table to negative deflections (odd force law); damper: to negative
    /// velocities; default false.
    #[serde(default)]
    pub symmetric: Option<Spanned<bool>>,
    /// \[m/s\] damper: velocities of its force–velocity table, strictly increasing (the forces
    /// in `force_n`).
    #[serde(default)]
    pub velocity_m_per_s: Option<Spanned<Vec<Spanned<f64>>>>,
    /// \[N\] friction: the constant part of the sliding force, ≥ 0.
    #[serde(default)]
    pub friction_force_n: Option<Spanned<f64>>,
    /// \[-\] friction: the coefficient that multiplies the force of `normal_element`, ≥ 0.
    #[serde(default)]
    pub friction_coefficient: Option<Spanned<f64>>,
    /// Friction: the force element whose force presses the friction surfaces together.
    #[serde(default)]
    pub normal_element: Option<Spanned<String>>,
    /// Friction: the signed local axis of `normal_element` along which its force on its body2
    /// presses the surfaces (`"z"`, `"-z"`, …), or `"any"` for the magnitude of its force.
    #[serde(default)]
    pub normal_direction: Option<Spanned<String>>,
    /// Planar friction: the plane of two local axes it acts in, e.g. `"xy"`.
    #[serde(default)]
    pub plane: Option<Spanned<String>>,
    /// Rotational friction: the local axis it acts about, `"x"`, `"y"` or `"z"`.
    #[serde(default)]
    pub about: Option<Spanned<String>>,
    /// \[N·m\] rotational friction: the constant part of the sliding moment, ≥ 0.
    #[serde(default)]
    pub friction_moment_nm: Option<Spanned<f64>>,
    /// \[m\] rotational friction: the radius at which the normal element's force rubs (the
    /// sliding moment's load-dependent part is coefficient × normal force × radius), > 0.
    #[serde(default)]
    pub friction_radius_m: Option<Spanned<f64>>,
}

/// A number, or three numbers (one per local axis). An array of any other length is refused
/// when read, with the length found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NumberOrTriple {
    /// One number.
    One(f64),
    /// Three numbers `[x, y, z]`.
    Three([f64; 3]),
}

impl<'de> Deserialize<'de> for NumberOrTriple {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ThreeVisitor { or_one: true })
    }
}

/// Exactly three numbers, read from an array of any length so that a wrong length is refused
/// with the length found. (serde reads `[f64; 3]` as a tuple of 3, and the TOML deserializer does
/// not report the elements left over: `[1, 2, 3, 4]` would silently become `[1, 2, 3]`.)
struct Three([f64; 3]);

impl<'de> Deserialize<'de> for Three {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match d.deserialize_seq(ThreeVisitor { or_one: false })? {
            NumberOrTriple::Three(a) => Ok(Three(a)),
            // not given by the visitor without `or_one`
            NumberOrTriple::One(_) => Err(de::Error::custom("expected an array of 3 numbers")),
        }
    }
}

/// Reads an array of exactly three numbers, or (`or_one`) also a single number.
struct ThreeVisitor {
    /// A single number is accepted too ([`NumberOrTriple`]).
    or_one: bool,
}

impl<'de> Visitor<'de> for ThreeVisitor {
    type Value = NumberOrTriple;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.or_one {
            f.write_str("a number or an array of 3 numbers")
        } else {
            f.write_str("an array of 3 numbers")
        }
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Self::Value, E> {
        if self.or_one {
            Ok(NumberOrTriple::One(x))
        } else {
            Err(E::invalid_type(de::Unexpected::Float(x), &self))
        }
    }

    fn visit_i64<E: de::Error>(self, x: i64) -> Result<Self::Value, E> {
        if self.or_one {
            Ok(NumberOrTriple::One(x as f64))
        } else {
            Err(E::invalid_type(de::Unexpected::Signed(x), &self))
        }
    }

    fn visit_u64<E: de::Error>(self, x: u64) -> Result<Self::Value, E> {
        if self.or_one {
            Ok(NumberOrTriple::One(x as f64))
        } else {
            Err(E::invalid_type(de::Unexpected::Unsigned(x), &self))
        }
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut a = [0.0; 3];
        let mut n = 0;
        while let Some(x) = seq.next_element::<f64>()? {
            if let Some(slot) = a.get_mut(n) {
                *slot = x;
            }
            n += 1;
        }
        if n == 3 {
            Ok(NumberOrTriple::Three(a))
        } else {
            // (where one number is accepted, say so: `[940e3]` for a key that takes `940e3`)
            Err(de::Error::custom(format!(
                "expected {}, found an array of {n} number{}",
                if self.or_one {
                    "a number (written without brackets) or an array of 3 numbers"
                } else {
                    "an array of 3 numbers"
                },
                if n == 1 { "" } else { "s" }
            )))
        }
    }
}

/// `deserialize_with` of the `[x, y, z]` keys: an optional, spanned array of exactly three
/// numbers ([`Three`]); another length is an error located at the array, naming the length.
fn three_numbers<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Spanned<[f64; 3]>>, D::Error> {
    let v = Option::<Spanned<Three>>::deserialize(d)?;
    Ok(v.map(|s| {
        let span = s.span();
        Spanned::new(span, s.into_inner().0)
    }))
}

/// Keys of the root table.
pub const ROOT_KEYS: &[&str] = &[
    "name",
    "description",
    "gravity_m_per_s2",
    "body",
    "wheelset",
    "force",
];
/// Keys of a `[[body]]`.
pub const BODY_KEYS: &[&str] = &[
    "name",
    "mass_kg",
    "inertia_kgm2",
    "products_kgm2",
    "position_m",
    "frozen",
];
/// Keys of a `[[wheelset]]`.
pub const WHEELSET_KEYS: &[&str] = &[
    "name",
    "mass_kg",
    "inertia_kgm2",
    "products_kgm2",
    "position_m",
    "nominal_radius_m",
    "back_to_back_mm",
    "running_circle_from_back_mm",
    "wheel_profile",
    "torque_nm",
    "torque_reaction",
    "frozen",
    "out_of_roundness",
];
/// Keys of a `[[force]]`.
pub const FORCE_KEYS: &[&str] = &[
    "name",
    "type",
    "body1",
    "body2",
    "point_m",
    "point2_m",
    "orientation_deg",
    "direction",
    "stiffness_n_per_m",
    "damping_ns_per_m",
    "rotational_stiffness_nm_per_rad",
    "rotational_damping_nms_per_rad",
    "deflection_mm",
    "force_n",
    "symmetric",
    "velocity_m_per_s",
    "friction_force_n",
    "friction_coefficient",
    "normal_element",
    "normal_direction",
    "plane",
    "about",
    "friction_moment_nm",
    "friction_radius_m",
];

impl VehicleSpec {
    /// Read a vehicle from TOML text, failing on any structural problem (syntax, unknown key,
    /// wrong type), all of them reported. `source_name` (usually the path) prefixes every
    /// message.
    pub fn from_toml_str(text: &str, source_name: &str) -> Result<VehicleSpec, VehicleError> {
        let (spec, problems) = VehicleSpec::parse_lenient(text, source_name);
        if problems.is_empty() {
            Ok(spec)
        } else {
            Err(VehicleError::Invalid { problems })
        }
    }

    /// Read a vehicle from TOML text, keeping whatever could be read: returns the spec (with
    /// wrongly typed values dropped) and the structural problems found. Used by
    /// [`crate::VehicleModel::from_toml_str`] to report structural and range problems together.
    pub fn parse_lenient(text: &str, source_name: &str) -> (VehicleSpec, Vec<Problem>) {
        let map = SourceMap::new(text);
        let mut sink = Sink::new(source_name, &map);
        let (root, errors) = DeTable::parse_recoverable(text);
        if !errors.is_empty() {
            for e in errors {
                sink.at(
                    e.span().as_ref(),
                    "",
                    format!("TOML syntax: {}", e.message().trim()),
                );
            }
            let problems = sink.problems;
            return (
                VehicleSpec {
                    source: map,
                    ..VehicleSpec::default()
                },
                problems,
            );
        }
        let root_span = root.span();
        let mut table = root.into_inner();
        let arrays = [
            ("body", table.remove("body")),
            ("wheelset", table.remove("wheelset")),
            ("force", table.remove("force")),
        ];
        let mut unreadable = Vec::new();
        let mut dropped = Vec::new();
        let mut spec: VehicleSpec = read_table(
            table,
            root_span,
            ROOT_KEYS,
            "vehicle: ",
            &mut sink,
            &mut dropped,
            as_is,
        )
        .unwrap_or_default();
        for (what, value) in arrays {
            let Some(value) = value else { continue };
            let span = value.span();
            let items = match value.into_inner() {
                DeValue::Array(items) => items,
                other => {
                    sink.at(
                        Some(&span),
                        what,
                        format!(
                            "{what}: expected an array of tables ([[{what}]]), found {}",
                            other.type_str()
                        ),
                    );
                    continue;
                }
            };
            for (i, item) in items.into_iter().enumerate() {
                let span = item.span();
                let DeValue::Table(t) = item.into_inner() else {
                    sink.at(
                        Some(&span),
                        what,
                        format!("{what}: expected a table ([[{what}]])"),
                    );
                    continue;
                };
                let prefix = match t.get("name").map(|v| v.get_ref()) {
                    Some(DeValue::String(s)) => format!("{what} '{s}': "),
                    _ => format!("{what} #{}: ", i + 1),
                };
                let name = match t.get("name").map(|v| v.get_ref()) {
                    Some(DeValue::String(s)) => Some(s.to_string()),
                    _ => None,
                };
                let ok = match what {
                    "body" => read_table::<BodySpec>(
                        t,
                        span.clone(),
                        BODY_KEYS,
                        &prefix,
                        &mut sink,
                        &mut dropped,
                        as_is,
                    )
                    .map(|b| spec.body.push(Spanned::new(span.clone(), b)))
                    .is_some(),
                    "wheelset" => read_table::<WheelsetSpec>(
                        t,
                        span.clone(),
                        WHEELSET_KEYS,
                        &prefix,
                        &mut sink,
                        &mut dropped,
                        as_is,
                    )
                    .map(|w| spec.wheelset.push(Spanned::new(span.clone(), w)))
                    .is_some(),
                    _ => read_table::<ForceSpec>(
                        t,
                        span.clone(),
                        FORCE_KEYS,
                        &prefix,
                        &mut sink,
                        &mut dropped,
                        as_is,
                    )
                    .map(|f| spec.force.push(Spanned::new(span.clone(), f)))
                    .is_some(),
                };
                if !ok && let Some(n) = name {
                    unreadable.push(n);
                }
            }
        }
        let problems = sink.problems;
        spec.unreadable_names = unreadable;
        spec.dropped_keys = dropped;
        spec.source = map;
        (spec, problems)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Why [`Three`] exists: serde reads `[f64; 3]` as a tuple of three, and the TOML
    /// deserializer (toml 1.2) does not report the elements left over, so a fourth number is
    /// dropped without a word. (Should a toml upgrade refuse it itself, the first assertion
    /// fails; `Three` stays correct either way.)
    #[test]
    fn a_plain_array_of_three_drops_a_fourth_number_and_three_numbers_refuses_it() {
        #[derive(Deserialize)]
        struct Plain {
            a: [f64; 3],
        }
        #[derive(Deserialize)]
        struct Checked {
            #[serde(default, deserialize_with = "three_numbers")]
            a: Option<Spanned<[f64; 3]>>,
        }
        let plain = toml::from_str::<Plain>("a = [1, 2, 3, 4]").map(|p| p.a);
        assert_eq!(plain.ok(), Some([1.0, 2.0, 3.0]));
        let short = toml::from_str::<Plain>("a = [1, 2]").map(|p| p.a);
        assert!(short.is_err(), "{short:?}");

        let e = toml::from_str::<Checked>("a = [1, 2, 3, 4]")
            .err()
            .map(|e| (e.message().to_owned(), e.span()));
        assert_eq!(
            e,
            Some((
                "expected an array of 3 numbers, found an array of 4 numbers".to_owned(),
                Some(4..16)
            ))
        );
        let ok = toml::from_str::<Checked>("a = [1, 2.5, -3]").map(|c| c.a.map(|a| *a.get_ref()));
        assert_eq!(ok.ok(), Some(Some([1.0, 2.5, -3.0])));
        let absent = toml::from_str::<Checked>("").map(|c| c.a.is_none());
        assert_eq!(absent.ok(), Some(true));
        let one = toml::from_str::<Checked>("a = 1")
            .err()
            .map(|e| e.message().to_owned());
        assert!(
            one.as_deref()
                .is_some_and(|m| m.contains("expected an array of 3 numbers")),
            "{one:?}"
        );
    }

    /// A number or three numbers; another length is refused with the length found.
    #[test]
    fn number_or_triple_reads_one_or_three_numbers_only() {
        #[derive(Deserialize)]
        struct K {
            k: NumberOrTriple,
        }
        let read = |t: &str| {
            toml::from_str::<K>(t)
                .map(|k| k.k)
                .map_err(|e| e.to_string())
        };
        assert_eq!(read("k = 5").ok(), Some(NumberOrTriple::One(5.0)));
        assert_eq!(read("k = 2.5e6").ok(), Some(NumberOrTriple::One(2.5e6)));
        assert_eq!(
            read("k = [1, 2, 3.5]").ok(),
            Some(NumberOrTriple::Three([1.0, 2.0, 3.5]))
        );
        for (text, needle) in [
            ("k = [1, 2, 3, 4]", "found an array of 4 numbers"),
            (
                "k = [1]",
                "a number (written without brackets) or an array of 3 numbers, found an array of 1 number",
            ),
            ("k = \"x\"", "expected a number or an array of 3 numbers"),
            ("k = [1, \"x\", 3]", "invalid type"),
        ] {
            let e = read(text).err();
            assert!(
                e.as_deref().is_some_and(|m| m.contains(needle)),
                "{text}: {e:?}"
            );
        }
    }
}
