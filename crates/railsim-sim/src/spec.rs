//! `SceneSpec`: the scene file as written, one to one with the TOML, in the file's units.
//!
//! Every value keeps its span so that [`crate::Scene::compile`] can report `file:line:col`.
//! Unknown keys are rejected (`deny_unknown_fields`, and a check of every table's keys before
//! serde runs, so that all unknown keys are reported, with a suggestion). The format is
//! documented in `docs/formats/scene.md`.
//!
//! Keys are optional at the serde level; which ones are required, and which combinations are
//! allowed, is checked by the compile step so that every problem is reported in one run. The
//! reader parses the root table and each sub-table (`[speed_profile]`, `[contact]`,
//! `[integrator]`, `[log]`, `[initial]`, `[assessment]`) separately; a value of the wrong type is reported,
//! dropped, and the table is read again, so one wrong type does not hide the next one.

use serde::Deserialize;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

pub use railsim_spec::FrictionSpec;
use railsim_spec::{as_is, friction_message, read_table};

use crate::error::{Problem, SceneError, Sink, SourceMap};

/// A whole scene file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Free-text name of the scene.
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// Free-text description.
    #[serde(default)]
    pub description: Option<Spanned<String>>,
    /// Vehicle file, relative to the scene file (required).
    #[serde(default)]
    pub vehicle: Option<Spanned<String>>,
    /// Track file, relative to the scene file (required).
    #[serde(default)]
    pub track: Option<Spanned<String>>,
    /// \[km/h\] constant speed (this or `[speed_profile]`).
    #[serde(default)]
    pub speed_kmh: Option<Spanned<f64>>,
    /// Speed against distance run (this or `speed_kmh`).
    #[serde(default)]
    pub speed_profile: Option<Spanned<SpeedProfileSpec>>,
    /// \[m\] track position s of the vehicle reference point (x = 0 of the vehicle frame) at
    /// t = 0; default: the rearmost wheelset at s = 0.
    #[serde(default)]
    pub start_m: Option<Spanned<f64>>,
    /// \[s\] simulated time (this or `distance_m`).
    #[serde(default)]
    pub duration_s: Option<Spanned<f64>>,
    /// \[m\] distance run (this or `duration_s`).
    #[serde(default)]
    pub distance_m: Option<Spanned<f64>>,
    /// Wheel/rail contact model; default `stripes`.
    #[serde(default)]
    pub contact: Option<Spanned<ContactSpec>>,
    /// ODE integrator; default `dopri5`.
    #[serde(default)]
    pub integrator: Option<Spanned<IntegratorSpec>>,
    /// What to log and where; defaults when absent.
    #[serde(default)]
    pub log: Option<Spanned<LogSpec>>,
    /// Initial disturbance of the leading wheelset; none when absent.
    #[serde(default)]
    pub initial: Option<Spanned<InitialSpec>>,
    /// Settings of the EN 14363 assessment of the run; defaults when absent.
    #[serde(default)]
    pub assessment: Option<Spanned<AssessmentSpec>>,
    /// Degrees of freedom held at their nominal value, as `"body.dof"` (e.g. `"ws1.spin"`).
    #[serde(default)]
    pub freeze: Option<Spanned<Vec<Spanned<String>>>>,
    /// Keys dropped by the reader because their value had the wrong type:
    /// `(table span start, key)`. The compile step does not report them as missing.
    #[serde(skip)]
    pub dropped_keys: Vec<(usize, String)>,
    /// Sub-tables that could not be read at all (their problems are already reported).
    #[serde(skip)]
    pub unreadable_tables: Vec<String>,
    /// Line index of the text this spec was read from (empty when built in code).
    #[serde(skip)]
    pub source: SourceMap,
}

/// `[speed_profile]`: speed against distance run, linear in between, constant beyond the ends.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedProfileSpec {
    /// \[m\] distance run since t = 0, starting at 0, strictly increasing (required).
    #[serde(default)]
    pub distance_m: Option<Spanned<Vec<Spanned<f64>>>>,
    /// \[km/h\] speed at each distance, positive (required).
    #[serde(default)]
    pub speed_kmh: Option<Spanned<Vec<Spanned<f64>>>>,
}

/// `[contact]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// `"linear"`, `"polach"`, `"fastsim"`, `"stripes"` (default) or `"halfspace"`.
    #[serde(default)]
    pub model: Option<Spanned<String>>,
    /// \[mm\] arc-length step of the contact search near contact; default 1.0.
    #[serde(default)]
    pub step_mm: Option<Spanned<f64>>,
    /// Coulomb friction coefficient of the wheel/rail pairs: a number (default 0.3), a table
    /// varying with the contact angle, or either per rail.
    #[serde(default)]
    pub friction: Option<Spanned<FrictionSpec>>,
    /// \[N\] `linear` model only: constant creep coefficient f11 = f22 (no spin terms); without
    /// it the `linear` model uses Kalker's coefficients.
    #[serde(default)]
    pub creep_coefficient_n: Option<Spanned<f64>>,
    /// Warm-start the contact search from each wheel's previous evaluation; default true.
    #[serde(default)]
    pub warm_start: Option<Spanned<bool>>,
    /// How the Hertz models find their contact points: `"point"` (default) or `"travel"`.
    #[serde(default)]
    pub hertz_search: Option<Spanned<String>>,
    /// Tangential solution of `stripes` and `halfspace`: `"fastrip"` (default) or `"fastsim"`.
    #[serde(default)]
    pub tangential: Option<Spanned<String>>,
    /// `polach` model only: Polach's reduction factors (docs/formats/scene.md).
    #[serde(default)]
    pub polach: Option<Spanned<PolachSpec>>,
    /// Friction falling with the slip velocity: `polach`, `fastsim` and `stripes`
    /// (docs/formats/scene.md).
    #[serde(default)]
    pub falling_friction: Option<Spanned<FallingFrictionSpec>>,
}

/// `[contact] polach`: Polach's extended creep-force model (Polach 2005), its reduction
/// factors; every key optional, with the 1999 model's values (1, 1).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolachSpec {
    /// \[-\] reduction factor k_A of the initial slope, in (0, 1].
    #[serde(default)]
    pub k_a: Option<Spanned<f64>>,
    /// \[-\] reduction factor k_S in the slip area, in (0, k_a].
    #[serde(default)]
    pub k_s: Option<Spanned<f64>>,
}

/// `[contact] falling_friction`: the friction μ0 ((1 − A) e^(−B w) + A) at slip velocity w
/// (Polach 2005); every key optional, with Coulomb friction's values (1, 0).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FallingFrictionSpec {
    /// \[-\] A: the friction at infinite slip velocity over the pair's friction, in [0, 1].
    #[serde(default)]
    pub ratio_at_infinite_slip: Option<Spanned<f64>>,
    /// \[s/m\] B: the decay rate of the friction with the slip velocity, in [0, 100].
    #[serde(default)]
    pub decay_s_per_m: Option<Spanned<f64>>,
}

/// `[integrator]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegratorSpec {
    /// `"dopri5"`, `"bs3"`, `"rk4"` or `"radau5"` (required in the table).
    #[serde(default)]
    pub method: Option<Spanned<String>>,
    /// \[-\] relative tolerance (`dopri5`, `bs3`, `radau5`); default 1e-6.
    #[serde(default)]
    pub rtol: Option<Spanned<f64>>,
    /// \[SI units of the state\] absolute tolerance (`dopri5`, `bs3`, `radau5`); default 1e-8.
    #[serde(default)]
    pub atol: Option<Spanned<f64>>,
    /// \[s\] fixed step (`rk4`, required there).
    #[serde(default)]
    pub step_s: Option<Spanned<f64>>,
    /// \[s\] largest step (`dopri5`, `bs3`, `radau5`); default unlimited.
    #[serde(default)]
    pub max_step_s: Option<Spanned<f64>>,
}

/// `[log]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LogSpec {
    /// MCAP file to write, relative to the working directory of the run; default
    /// `out/run.mcap`.
    #[serde(default)]
    pub path: Option<Spanned<String>>,
    /// \[Hz\] logging rate; default 200.
    #[serde(default)]
    pub rate_hz: Option<Spanned<f64>>,
    /// Topics to log: any of `bodies`, `bogie_frames`, `carbody`, `contact`, `elements`,
    /// `wheelsets`, `tf`; default all but `elements`.
    #[serde(default)]
    pub topics: Option<Spanned<Vec<Spanned<String>>>>,
}

/// `[initial]`: the initial state, and a disturbance of the leading wheelset at t = 0.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// `"static"` (default: the static equilibrium on straight level track) or
    /// `"quasi-static"` (the steady state at the start, which may lie in a curve).
    #[serde(default)]
    pub state: Option<Spanned<String>>,
    /// \[mm\] lateral offset, positive to the left; default 0.
    #[serde(default)]
    pub lateral_offset_mm: Option<Spanned<f64>>,
    /// \[mrad\] yaw angle, positive nose-left; default 0.
    #[serde(default)]
    pub yaw_mrad: Option<Spanned<f64>>,
}

/// `[assessment]`: settings of the EN 14363 track-loading and running-stability assessment.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssessmentSpec {
    /// \[-\] α of Prud'homme's track-shift limit: 1 for locomotives and passenger vehicles
    /// (default), 0.85 for freight wagons.
    #[serde(default)]
    pub alpha: Option<Spanned<f64>>,
    /// \[Hz\] instability frequency f0 of the stability criterion's band-pass; default: the
    /// dominant frequency of the track-shift force.
    #[serde(default)]
    pub instability_frequency_hz: Option<Spanned<f64>>,
    /// \[Hz\] the rate of the samples the assessment is made from, a whole multiple of the log
    /// rate; default: the smallest such multiple at or above 1 kHz (2 kHz for the Hertz models).
    #[serde(default)]
    pub rate_hz: Option<Spanned<f64>>,
    /// The carbody's measuring points; default: its centre and above each bogie.
    #[serde(default)]
    pub comfort_points: Option<Spanned<Vec<Spanned<ComfortPointSpec>>>>,
    /// \[-\] limit of (Y/Q)2m on tangent track and large radii; default 0.8.
    #[serde(default)]
    pub y_over_q_limit: Option<Spanned<f64>>,
    /// \[-\] limit of (Y/Q)2m in circular curves of small radius; default 1.2.
    #[serde(default)]
    pub y_over_q_limit_small_radius: Option<Spanned<f64>>,
    /// \[m\] the radius below which a curve's (Y/Q)2m limit is the small-radius one; default 250.
    #[serde(default)]
    pub small_radius_m: Option<Spanned<f64>>,
    /// \[kN\] limit of the vertical wheel force Q; default 90 kN + Q0 capped by the speed.
    #[serde(default)]
    pub q_limit_kn: Option<Spanned<f64>>,
    /// \[kN\] limit of the quasi-static guiding force Y_qst; default 60.
    #[serde(default)]
    pub y_qst_limit_kn: Option<Spanned<f64>>,
    /// \[kN\] limit of the quasi-static vertical wheel force Q_qst; default 145.
    #[serde(default)]
    pub q_qst_limit_kn: Option<Spanned<f64>>,
    /// The W_b of N_MV's vertical acceleration: "en12299" (default) or "iso2631-4".
    #[serde(default)]
    pub vertical_weighting: Option<Spanned<String>>,
    /// \[m\] length of the track sections of the per-section statistics; default: none.
    #[serde(default)]
    pub section_length_m: Option<Spanned<f64>>,
    /// \[-\] k of the estimate mean + k s over the sections; default: none.
    #[serde(default)]
    pub section_k: Option<Spanned<f64>>,
}

/// One `[[assessment.comfort_points]]` entry: a measuring point on the carbody.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComfortPointSpec {
    /// Name in the summary and the log.
    pub name: Spanned<String>,
    /// \[m\] offset from the carbody's centre of gravity, forward; default 0.
    #[serde(default)]
    pub x_m: Option<Spanned<f64>>,
    /// \[m\] offset to the left; default 0.
    #[serde(default)]
    pub y_m: Option<Spanned<f64>>,
    /// \[m\] offset upward (a floor below the centre of gravity: negative); default 0.
    #[serde(default)]
    pub z_m: Option<Spanned<f64>>,
}

/// Keys of the root table.
pub const ROOT_KEYS: &[&str] = &[
    "name",
    "description",
    "vehicle",
    "track",
    "speed_kmh",
    "speed_profile",
    "start_m",
    "duration_s",
    "distance_m",
    "contact",
    "integrator",
    "log",
    "initial",
    "assessment",
    "freeze",
];
/// Keys of `[speed_profile]`.
pub const SPEED_PROFILE_KEYS: &[&str] = &["distance_m", "speed_kmh"];
/// Keys of `[contact]`.
pub const CONTACT_KEYS: &[&str] = &[
    "model",
    "step_mm",
    "friction",
    "creep_coefficient_n",
    "warm_start",
    "hertz_search",
    "tangential",
    "polach",
    "falling_friction",
];
/// Keys of `[integrator]`.
pub const INTEGRATOR_KEYS: &[&str] = &["method", "rtol", "atol", "step_s", "max_step_s"];
/// Keys of `[log]`.
pub const LOG_KEYS: &[&str] = &["path", "rate_hz", "topics"];
/// Keys of `[initial]`.
pub const INITIAL_KEYS: &[&str] = &["state", "lateral_offset_mm", "yaw_mrad"];
/// Keys of `[assessment]`.
pub const ASSESSMENT_KEYS: &[&str] = &[
    "alpha",
    "instability_frequency_hz",
    "rate_hz",
    "comfort_points",
    "y_over_q_limit",
    "y_over_q_limit_small_radius",
    "small_radius_m",
    "q_limit_kn",
    "y_qst_limit_kn",
    "q_qst_limit_kn",
    "vertical_weighting",
    "section_length_m",
    "section_k",
];

const SUBTABLES: [(&str, &[&str]); 6] = [
    ("speed_profile", SPEED_PROFILE_KEYS),
    ("contact", CONTACT_KEYS),
    ("integrator", INTEGRATOR_KEYS),
    ("log", LOG_KEYS),
    ("initial", INITIAL_KEYS),
    ("assessment", ASSESSMENT_KEYS),
];

/// A sub-table taken out of the root: name, known keys, value.
type Subtable<'a> = (
    &'static str,
    &'static [&'static str],
    Option<Spanned<DeValue<'a>>>,
);

impl SceneSpec {
    /// Read a scene from TOML text, failing on any structural problem (syntax, unknown key,
    /// wrong type), all of them reported. `source_name` (usually the path) prefixes every
    /// message.
    pub fn from_toml_str(text: &str, source_name: &str) -> Result<SceneSpec, SceneError> {
        let (spec, problems) = SceneSpec::parse_lenient(text, source_name);
        if problems.is_empty() {
            Ok(spec)
        } else {
            Err(SceneError::Invalid { problems })
        }
    }

    /// Read a scene from TOML text, keeping whatever could be read: returns the spec (with
    /// wrongly typed values dropped) and the structural problems found. Used by
    /// [`crate::Scene::from_toml_str`] to report structural and range problems together.
    pub fn parse_lenient(text: &str, source_name: &str) -> (SceneSpec, Vec<Problem>) {
        let map = SourceMap::new(text);
        let mut sink = Sink::new(source_name, &map);
        let (root, errors) = DeTable::parse_recoverable(text);
        if !errors.is_empty() {
            for e in errors {
                let span = e.span().unwrap_or(0..0);
                sink.at(
                    Some(&span),
                    "",
                    format!("TOML syntax: {}", e.message().trim()),
                );
            }
            let problems = sink.problems;
            return (
                SceneSpec {
                    source: map,
                    ..SceneSpec::default()
                },
                problems,
            );
        }
        let root_span = root.span();
        let mut table = root.into_inner();
        let subtables: Vec<Subtable<'_>> = SUBTABLES
            .iter()
            .map(|(name, keys)| (*name, *keys, table.remove(*name)))
            .collect();
        let mut dropped = Vec::new();
        let mut spec: SceneSpec = read_table(
            table,
            root_span,
            ROOT_KEYS,
            "",
            &mut sink,
            &mut dropped,
            as_is,
        )
        .unwrap_or_default();
        let mut unreadable = Vec::new();
        for (name, keys, value) in subtables {
            let Some(value) = value else { continue };
            let span = value.span();
            let DeValue::Table(t) = value.into_inner() else {
                sink.at(
                    Some(&span),
                    name,
                    format!("{name}: expected a table ([{name}] or {name} = {{ ... }})"),
                );
                unreadable.push(name.to_owned());
                continue;
            };
            let label = format!("[{name}] ");
            // Read the subtable into `spec.$field`; false when it could not be read.
            macro_rules! read_into {
                ($field:ident) => {
                    read_into!($field, as_is)
                };
                ($field:ident, $rewrite:expr) => {
                    read_table(
                        t,
                        span.clone(),
                        keys,
                        &label,
                        &mut sink,
                        &mut dropped,
                        $rewrite,
                    )
                    .map(|v| spec.$field = Some(Spanned::new(span.clone(), v)))
                    .is_some()
                };
            }
            let ok = match name {
                "speed_profile" => read_into!(speed_profile),
                "contact" => read_into!(contact, friction_message),
                "integrator" => read_into!(integrator),
                "log" => read_into!(log),
                "initial" => read_into!(initial),
                _ => read_into!(assessment),
            };
            if !ok {
                unreadable.push(name.to_owned());
            }
        }
        let mut problems = sink.problems;
        problems.sort_by_key(|p| (p.line, p.col));
        spec.dropped_keys = dropped;
        spec.unreadable_tables = unreadable;
        spec.source = map;
        (spec, problems)
    }
}
