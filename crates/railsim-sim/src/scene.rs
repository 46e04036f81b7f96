//! `Scene`: the compiled scene (SI, vehicle and track compiled, every choice checked).

use std::ops::Range;
use std::path::{Component, Path, PathBuf};

use railsim_contact::{
    ContactModelKind, ContactOptions, FallingFriction, Friction, HertzSearch, PolachAdhesion,
    Tangential,
};
use railsim_ode::Method;
use railsim_spec::short_number;
use railsim_track::{SegmentKind, TrackError, TrackModel, TrackSpec};
use railsim_vehicle::{Dof, DofKind, Endpoint, Member, VehicleError, VehicleModel, WheelsetId};
use toml::Spanned;

use crate::assess::{
    AssessOptions, ComfortPoint, DEFAULT_ASSESSMENT_RATE_HZ, STABILITY_HALF_BAND, SectionOptions,
    VerticalWeighting, default_assessment_rate, stability_band,
};
use crate::error::{Problem, SceneError, SimError, Sink, did_you_mean};
use crate::spec::{
    AssessmentSpec, ContactSpec, FallingFrictionSpec, FrictionSpec, InitialSpec, IntegratorSpec,
    LogSpec, PolachSpec, SceneSpec, SpeedProfileSpec,
};

/// \[-\] a rigid wheelbase `a` needs curves of radius R ≥ this × a (see
/// [`required_curve_radius`]).
pub const RADIUS_PER_WHEELBASE: f64 = 20.0;
/// \[km/h\] largest speed accepted.
pub const MAX_SPEED_KMH: f64 = 1500.0;
/// \[km/h\] lowest speed accepted (2.8 mm/s): the contact's creepages are relative to the
/// speed, and a vehicle at rest has none. Walking pace and below are slow to integrate (the
/// creep forces act as very stiff dampers) but work.
pub const MIN_SPEED_KMH: f64 = 0.01;
/// \[s\] smallest `max_step_s` accepted (below it a run of seconds takes millions of steps).
pub const MIN_MAX_STEP_S: f64 = 1e-6;

/// \[s\] longest duration accepted (one day).
pub const MAX_DURATION_S: f64 = 86_400.0;
/// \[-\] range of the relative tolerance of the adaptive integrators.
pub const RTOL_RANGE: (f64, f64) = (1e-12, 1e-2);
/// \[SI units of the state\] range of the absolute tolerance of the adaptive integrators.
pub const ATOL_RANGE: (f64, f64) = (1e-15, 1e-2);
/// \[s\] range of the fixed step of `rk4`.
pub const STEP_RANGE_S: (f64, f64) = (1e-7, 1e-2);
/// \[s\] largest `max_step_s` accepted.
pub const MAX_STEP_LIMIT_S: f64 = 1.0;
/// \[-\] default relative tolerance of `dopri5` and `radau5`.
pub const DEFAULT_RTOL: f64 = 1e-6;
/// \[SI units of the state\] default absolute tolerance of `dopri5` and `radau5`.
pub const DEFAULT_ATOL: f64 = 1e-8;
/// \[-\] friction coefficient when the scene gives none.
pub const DEFAULT_FRICTION: f64 = 0.3;
/// \[N\] accepted constant creep coefficients of the `linear` model.
const CREEP_COEFFICIENT_RANGE_N: (f64, f64) = (1e4, 1e10);
/// \[mm\] range of the contact search step `step_mm` (that of the contact crate).
pub const CONTACT_STEP_RANGE_MM: (f64, f64) = (1e-3, 5.0);
/// \[Hz\] largest logging rate.
pub const MAX_LOG_RATE_HZ: f64 = 10_000.0;
/// \[Hz\] logging rate when the file gives none.
pub const DEFAULT_LOG_RATE_HZ: f64 = 200.0;

/// \[m\] the range of `[assessment] section_length_m`: from a few 2 m windows' worth of
/// sliding means up to 100 km.
const SECTION_LENGTH_RANGE: (f64, f64) = (10.0, 1e5);

/// \[Hz\] the largest `[assessment] rate_hz`.
pub const MAX_ASSESSMENT_RATE_HZ: f64 = 100e3;
/// \[Hz\] largest instability frequency of `[assessment]` (hunting of wheelsets and bogies lies
/// far below).
pub const MAX_INSTABILITY_HZ: f64 = 50.0;
/// \[m\] largest offset of a comfort point from the carbody's centre of gravity.
pub const MAX_COMFORT_OFFSET: f64 = 50.0;
/// Log file when the file gives none.
pub const DEFAULT_LOG_PATH: &str = "out/run.mcap";
/// \[mm\] largest |lateral_offset_mm| of the initial disturbance (S1002 on UIC60 1:40 is in
/// flange contact from about 8–9 mm).
pub const MAX_INITIAL_OFFSET_MM: f64 = 10.0;
/// \[mrad\] largest |yaw_mrad| of the initial disturbance.
pub const MAX_INITIAL_YAW_MRAD: f64 = 20.0;
/// Integrator names accepted in `[integrator] method`.
pub const INTEGRATOR_NAMES: [&str; 4] = ["dopri5", "bs3", "rk4", "radau5"];

/// What a run logs (`[log] topics`); the topic names are those of `railsim-log`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Topic {
    /// Per body state (pose, velocity): `/bodies/<name>`.
    Bodies,
    /// Per wheel and patch contact results: `/contact/<wheelset>/<side>`.
    Contact,
    /// Per wheelset Y, Q, Y/Q, angle of attack: `/wheelsets/<n>`.
    Wheelsets,
    /// Foxglove frame transforms: `/tf`.
    Tf,
    /// Per carbody comfort point, the accelerometer's reading: `/carbody/<n>`.
    Carbody,
    /// Per bogie frame and wheelset above which it is measured, the accelerometer's reading:
    /// `/bogie_frames/<n>`.
    BogieFrames,
    /// Per suspension force element, its deflections, forces and state: `/elements/<name>`.
    Elements,
}

impl Topic {
    /// All topics, in file-name order.
    pub const ALL: [Topic; 7] = [
        Topic::Bodies,
        Topic::BogieFrames,
        Topic::Carbody,
        Topic::Contact,
        Topic::Elements,
        Topic::Wheelsets,
        Topic::Tf,
    ];
    /// The topics of a scene without `[log] topics`: all but the force elements (one topic per
    /// element; asked for by name).
    pub const DEFAULT: [Topic; 6] = [
        Topic::Bodies,
        Topic::BogieFrames,
        Topic::Carbody,
        Topic::Contact,
        Topic::Wheelsets,
        Topic::Tf,
    ];
    /// The name as written in `[log] topics`.
    pub fn name(self) -> &'static str {
        match self {
            Topic::Bodies => "bodies",
            Topic::Contact => "contact",
            Topic::Wheelsets => "wheelsets",
            Topic::Tf => "tf",
            Topic::Carbody => "carbody",
            Topic::BogieFrames => "bogie_frames",
            Topic::Elements => "elements",
        }
    }
}

/// How long a run is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunLength {
    /// \[s\] simulated time.
    Duration(f64),
    /// \[m\] distance run by the vehicle reference point.
    Distance(f64),
}

/// Speed against distance run: piecewise linear in distance, constant beyond the ends. A
/// constant speed is a profile of one point.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedProfile {
    distance: Vec<f64>,
    speed: Vec<f64>,
}

impl SpeedProfile {
    /// A constant speed \[m/s\] (must be positive).
    pub fn constant(speed: f64) -> SpeedProfile {
        SpeedProfile {
            distance: vec![0.0],
            speed: vec![speed],
        }
    }

    /// A profile from points: distances \[m\] starting at 0, strictly increasing; speeds
    /// \[m/s\], positive. `None` when these conditions do not hold.
    pub fn from_points(distance: Vec<f64>, speed: Vec<f64>) -> Option<SpeedProfile> {
        let ok = !distance.is_empty()
            && distance.len() == speed.len()
            && distance[0] == 0.0
            && distance.windows(2).all(|w| w[1] > w[0] && w[1].is_finite())
            && speed.iter().all(|v| v.is_finite() && *v > 0.0);
        ok.then_some(SpeedProfile { distance, speed })
    }

    /// \[m\] the distances of the points.
    pub fn distances(&self) -> &[f64] {
        &self.distance
    }
    /// \[m/s\] the speeds of the points.
    pub fn speeds(&self) -> &[f64] {
        &self.speed
    }
    /// Whether the speed is the same everywhere.
    pub fn is_constant(&self) -> bool {
        self.speed.iter().all(|v| *v == self.speed[0])
    }

    /// \[m/s\] speed after distance `d` \[m\] run.
    pub fn speed_at(&self, d: f64) -> f64 {
        let n = self.distance.len();
        if d <= self.distance[0] || n == 1 {
            return self.speed[0];
        }
        if d >= self.distance[n - 1] {
            return self.speed[n - 1];
        }
        let i = self.distance.partition_point(|&x| x <= d) - 1;
        let (d0, d1) = (self.distance[i], self.distance[i + 1]);
        let (v0, v1) = (self.speed[i], self.speed[i + 1]);
        v0 + (v1 - v0) * (d - d0) / (d1 - d0)
    }

    /// \[s\] time to run distance `d` \[m\] ≥ 0. With v linear in distance on an interval,
    /// v = v0 + k·(d − d0), the time is ∫ dd / v = ln(v / v0) / k.
    pub fn time_at(&self, d: f64) -> f64 {
        let mut t = 0.0;
        for i in 0..self.distance.len() {
            let d0 = self.distance[i];
            let v0 = self.speed[i];
            let Some(&d1) = self.distance.get(i + 1) else {
                return t + (d - d0).max(0.0) / v0;
            };
            let v1 = self.speed[i + 1];
            let k = (v1 - v0) / (d1 - d0);
            let de = d.min(d1) - d0;
            if de <= 0.0 {
                return t;
            }
            t += interval_time(v0, k, de);
            if d <= d1 {
                return t;
            }
        }
        t
    }

    /// \[m\] distance run at time `t` \[s\] ≥ 0 (the inverse of [`SpeedProfile::time_at`]).
    pub fn distance_at(&self, t: f64) -> f64 {
        let mut left = t.max(0.0);
        for i in 0..self.distance.len() {
            let d0 = self.distance[i];
            let v0 = self.speed[i];
            let Some(&d1) = self.distance.get(i + 1) else {
                return d0 + v0 * left;
            };
            let v1 = self.speed[i + 1];
            let k = (v1 - v0) / (d1 - d0);
            let dt = interval_time(v0, k, d1 - d0);
            if left <= dt {
                // v0·(e^{k·t} − 1)/k, written with exp_m1 for k → 0.
                let dd = if k.abs() < 1e-12 {
                    v0 * left
                } else {
                    v0 * (k * left).exp_m1() / k
                };
                return d0 + dd;
            }
            left -= dt;
        }
        unreachable!("a profile has at least one point")
    }
}

/// \[s\] time to run `dd` \[m\] from speed `v0` \[m/s\] with dv/dd = `k` \[1/s\].
fn interval_time(v0: f64, k: f64, dd: f64) -> f64 {
    if (k * dd / v0).abs() < 1e-12 {
        dd / v0
    } else {
        (k * dd / v0).ln_1p() / k
    }
}

/// Log settings (`[log]`).
#[derive(Debug, Clone, PartialEq)]
pub struct LogOptions {
    /// MCAP file to write, as written in the scene (relative paths are relative to the working
    /// directory of the run).
    pub path: PathBuf,
    /// \[Hz\] logging rate.
    pub rate_hz: f64,
    /// Topics to log, in the order given, without duplicates.
    pub topics: Vec<Topic>,
}

/// Initial disturbance of the leading wheelset (`[initial]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialDisturbance {
    /// The leading wheelset (largest x in the vehicle frame).
    pub wheelset: WheelsetId,
    /// \[m\] lateral offset, positive to the left.
    pub lateral_offset: f64,
    /// \[rad\] yaw angle, positive nose-left.
    pub yaw: f64,
}

/// Which state a run starts from (`[initial] state`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InitialState {
    /// The static equilibrium on straight level track: every member on its own frame's centre
    /// line, each wheelset settled on its rails under its static load (docs/models/dynamics.md).
    /// The vehicle must start on a tangent without cant.
    #[default]
    Static,
    /// The steady state at the start (`f(0, x) = 0`: no acceleration relative to the
    /// track-following frames), found by Newton's method as for quasi-static curving
    /// (`crate::curving::quasi_static_start`). The vehicle may start inside a curve, where
    /// curvature and cant are constant along it. A disturbance is added to the steady state and
    /// held while the rest of the vehicle balances about it.
    QuasiStatic,
}

impl InitialState {
    /// Every initial state, in the order of the scene format's docs.
    pub const ALL: [InitialState; 2] = [InitialState::Static, InitialState::QuasiStatic];

    /// The name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            InitialState::Static => "static",
            InitialState::QuasiStatic => "quasi-static",
        }
    }
}

/// The longest rigid wheelset base of a vehicle: two wheelsets attached by force elements to the
/// same body (a bogie frame, or the carbody of a two-axle vehicle), or to each other.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidWheelbase {
    /// \[m\] distance in x between the front and rear wheelsets of the group.
    pub length: f64,
    /// The front wheelset of the group.
    pub front: WheelsetId,
    /// The rear wheelset of the group.
    pub rear: WheelsetId,
}

/// The longest rigid wheelbase of `vehicle`, if any two wheelsets are held by the same body.
///
/// Wheelsets joined by a force element to the same rigid body (not the `track` frame), or to
/// each other, form a group; the group's wheelbase is its extent in x. A single wheelset, free
/// or sprung to the track, has none.
pub fn longest_rigid_wheelbase(vehicle: &VehicleModel) -> Option<RigidWheelbase> {
    let n = vehicle.wheelsets().len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_on_body: Vec<Option<usize>> = vec![None; vehicle.bodies().len()];
    for f in vehicle.forces() {
        let (a, b) = (f.body1, f.body2);
        let pair = match (a, b) {
            (Endpoint::Member(Member::Wheelset(w)), Endpoint::Member(Member::Wheelset(v))) => {
                Some((w.index(), v.index()))
            }
            (Endpoint::Member(Member::Wheelset(w)), Endpoint::Member(Member::Body(body)))
            | (Endpoint::Member(Member::Body(body)), Endpoint::Member(Member::Wheelset(w))) => {
                match first_on_body[body.index()] {
                    None => {
                        first_on_body[body.index()] = Some(w.index());
                        None
                    }
                    Some(v) => Some((w.index(), v)),
                }
            }
            _ => None,
        };
        if let Some((i, j)) = pair {
            let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
            parent[ri] = rj;
        }
    }
    let mut best: Option<RigidWheelbase> = None;
    for r in 0..n {
        let members: Vec<usize> = (0..n).filter(|&i| root(&mut parent, i) == r).collect();
        if members.len() < 2 {
            continue;
        }
        let x = |i: usize| vehicle.wheelsets()[i].position[0];
        let front = *members
            .iter()
            .max_by(|a, b| x(**a).total_cmp(&x(**b)))
            .expect("two members");
        let rear = *members
            .iter()
            .min_by(|a, b| x(**a).total_cmp(&x(**b)))
            .expect("two members");
        let length = x(front) - x(rear);
        if best.as_ref().is_none_or(|b| length > b.length) {
            best = Some(RigidWheelbase {
                length,
                front: vehicle
                    .wheelset_id(&vehicle.wheelsets()[front].name)
                    .expect("exists"),
                rear: vehicle
                    .wheelset_id(&vehicle.wheelsets()[rear].name)
                    .expect("exists"),
            });
        }
    }
    best
}

/// \[m\] the smallest curve radius a vehicle accepts: [`RADIUS_PER_WHEELBASE`] × its longest
/// rigid wheelbase `a`, 0 when it has none (the track's own limit of 50 m still applies).
///
/// Criterion: a rigid wheelbase `a` centred radially on a curve of radius R meets the rails
/// with an angle of attack of about a/(2R) at each end wheelset. R ≥ 20·a keeps it at or below
/// 25 mrad, beyond which flange climbing and wear make a run meaningless for this simulator
/// (for the Manchester bogie, a = 2.56 m: R ≥ 51.2 m).
pub fn required_curve_radius(vehicle: &VehicleModel) -> f64 {
    longest_rigid_wheelbase(vehicle).map_or(0.0, |w| RADIUS_PER_WHEELBASE * w.length)
}

/// The compiled scene: immutable, SI, everything a run needs, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Name of the scene (the file's `name`, else the source name).
    pub name: String,
    /// The source name given to compile (usually the scene file's path).
    pub source: String,
    /// The vehicle file, resolved from the scene file's directory.
    pub vehicle_file: PathBuf,
    /// The compiled vehicle.
    pub vehicle: VehicleModel,
    /// The track file, resolved from the scene file's directory.
    pub track_file: PathBuf,
    /// The compiled track.
    pub track: TrackModel,
    /// Speed against distance run.
    pub speed: SpeedProfile,
    /// \[m\] track position s of the vehicle reference point (x = 0) at t = 0.
    pub start: f64,
    /// How long the run is.
    pub length: RunLength,
    /// Contact model and options for every wheel.
    pub contact: ContactOptions,
    /// Coulomb friction of the wheel/rail pairs on the left (`[0]`) and the right rail, each
    /// constant or varying with the contact angle (a rail section may replace it).
    pub friction: [Friction; 2],
    /// Warm-start each wheel's contact search from its previous evaluation (same patches and
    /// forces as a cold search to within the search's angle tolerance; docs/models/contact.md).
    pub warm_start: bool,
    /// The integration method and its settings.
    pub integrator: Method,
    /// What to log and where.
    pub log: LogOptions,
    /// Initial disturbance of the leading wheelset (zero when the file has no `[initial]`).
    pub initial: InitialDisturbance,
    /// The state the run starts from (`[initial] state`; [`InitialState::Static`] by default).
    pub initial_state: InitialState,
    /// Degrees of freedom frozen by the scene (in addition to those the vehicle file freezes).
    pub frozen: Vec<Dof>,
    /// Settings of the EN 14363 assessment of the run's track-shift force (`[assessment]`).
    pub assessment: AssessOptions,
}

impl Scene {
    /// The assessment's samples per log sample: `[assessment] rate_hz` over the log rate, or by
    /// default the fewest that reach the contact model's
    /// [`crate::assess::default_assessment_rate`] (docs/models/dynamics.md, "Aliasing").
    pub fn assessment_samples_per_log(&self) -> usize {
        self.assessment.samples_per_log(
            self.log.rate_hz,
            default_assessment_rate(self.contact.model),
        )
    }

    /// \[Hz\] the rate of the assessment's samples ([`Scene::assessment_samples_per_log`]
    /// times the log rate).
    pub fn assessment_rate(&self) -> f64 {
        self.log.rate_hz * self.assessment_samples_per_log() as f64
    }

    /// Sample the run at the log rate only: for runs whose results come from the log's samples
    /// (a study's callbacks), where the assessment's samples between them would cost recording
    /// evaluations and give nothing, and for re-running a log written before stop 33, when every
    /// run was sampled so.
    pub fn sample_at_log_rate(&mut self) {
        self.assessment.rate_hz = Some(self.log.rate_hz);
    }

    /// The data files the scene read besides the scene, vehicle and track files: the vehicle's
    /// wheel profile files, then the track's rail profile and irregularity files, each once.
    pub fn data_files(&self) -> Vec<&Path> {
        let mut files = self.vehicle.data_files();
        for path in self.track.data_files() {
            if !files.contains(&path) {
                files.push(path);
            }
        }
        files
    }

    /// Read and compile a scene file; the vehicle and track paths are resolved from its
    /// directory.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
            file: name.clone(),
            message: e.to_string(),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        Scene::from_toml_str(&text, &name, base)
    }

    /// Read and compile scene TOML text. Every problem (syntax, unknown keys, wrong types,
    /// missing keys, ranges, names, and the problems of the vehicle and track files) is
    /// reported in one [`SceneError::Invalid`].
    pub fn from_toml_str(
        text: &str,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<Scene, SceneError> {
        let (spec, mut problems) = SceneSpec::parse_lenient(text, source_name);
        if problems
            .iter()
            .any(|p| p.message.starts_with("TOML syntax"))
        {
            return Err(SceneError::Invalid { problems });
        }
        match Scene::compile(&spec, source_name, base_dir) {
            Ok(scene) if problems.is_empty() => Ok(scene),
            Ok(_) => Err(SceneError::Invalid { problems }),
            Err(SceneError::Invalid { problems: more }) => {
                // The scene file's problems first, in file order, then the other files'.
                let (mine, others): (Vec<Problem>, Vec<Problem>) =
                    more.into_iter().partition(|p| p.file == source_name);
                problems.extend(mine);
                problems.sort_by_key(|p| (p.line, p.col));
                problems.extend(others);
                Err(SceneError::Invalid { problems })
            }
            Err(e) => Err(e),
        }
    }

    /// Compile a spec: load and compile the vehicle and track it refers to (paths relative to
    /// `base_dir`), convert to SI, and check every value and the combinations (the run fits on
    /// the track, the track's curves suit the vehicle's wheelbase, frozen degrees of freedom
    /// exist). `source_name` prefixes the scene's messages; the vehicle's and track's problems
    /// keep their own file, line and column.
    ///
    /// ```
    /// use std::path::Path;
    /// use railsim_sim::{RunLength, Scene, SceneSpec};
    /// let text = r#"
    /// vehicle = "vehicles/wheelset_springs.toml"
    /// track = "tracks/straight.toml"
    /// speed_kmh = 180
    /// duration_s = 2
    /// [integrator]
    /// method = "rk4"
    /// step_s = 1e-5
    /// "#;
    /// let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    /// let spec = SceneSpec::from_toml_str(text, "doc.toml").unwrap();
    /// let scene = Scene::compile(&spec, "doc.toml", &root).unwrap();
    /// assert_eq!(scene.speed.speed_at(0.0), 50.0);
    /// assert_eq!(scene.length, RunLength::Duration(2.0));
    /// assert!((scene.distance() - 100.0).abs() < 1e-9);
    /// ```
    pub fn compile(
        spec: &SceneSpec,
        source_name: &str,
        base_dir: &Path,
    ) -> Result<Scene, SceneError> {
        let mut c = Compiler {
            sink: Sink::new(source_name, &spec.source),
            dropped: &spec.dropped_keys,
            unreadable: &spec.unreadable_tables,
            external: Vec::new(),
        };
        let scene = c.compile(spec, source_name, base_dir);
        let mut problems = c.sink.problems;
        problems.sort_by_key(|p| (p.line, p.col));
        problems.extend(c.external);
        match scene {
            Some(scene) if problems.is_empty() => Ok(scene),
            _ => Err(SceneError::Invalid { problems }),
        }
    }

    /// \[m\] distance the vehicle runs.
    pub fn distance(&self) -> f64 {
        match self.length {
            RunLength::Distance(d) => d,
            RunLength::Duration(t) => self.speed.distance_at(t),
        }
    }

    /// \[s\] simulated time of the run.
    pub fn duration(&self) -> f64 {
        match self.length {
            RunLength::Duration(t) => t,
            RunLength::Distance(d) => self.speed.time_at(d),
        }
    }

    /// A copy of this scene for a study (`crate::stability`): the same vehicle, track, start,
    /// contact, integrator and log settings, with `speed`, `length` and a lateral offset
    /// \[m\] of the leading wheelset (its yaw disturbance kept), starting from the static
    /// equilibrium ([`InitialState::Static`]: a study places its vehicle on its own track,
    /// straight where it starts). Checked like a scene file:
    /// the offset within ±[`MAX_INITIAL_OFFSET_MM`] and not on a frozen lateral degree of
    /// freedom (unless zero), and the run on the track.
    pub fn study(
        &self,
        speed: SpeedProfile,
        length: RunLength,
        lateral_offset: f64,
    ) -> Result<Scene, SimError> {
        let bad = |message: String| SimError::Study { message };
        let max = MAX_INITIAL_OFFSET_MM * 1e-3;
        if !(lateral_offset.is_finite() && lateral_offset.abs() <= max) {
            return Err(bad(format!(
                "study of scene '{}': the lateral offset must lie in [-{MAX_INITIAL_OFFSET_MM}, {MAX_INITIAL_OFFSET_MM}] mm, found {} mm",
                self.name,
                lateral_offset * 1e3
            )));
        }
        let dof = Dof {
            member: Member::Wheelset(self.initial.wheelset),
            kind: DofKind::Y,
        };
        if lateral_offset != 0.0 && self.is_frozen(dof) {
            return Err(bad(format!(
                "study of scene '{}': the leading wheelset's lateral displacement is frozen; a lateral offset has no effect",
                self.name
            )));
        }
        let mut s = self.clone();
        s.speed = speed;
        s.length = length;
        s.initial.lateral_offset = lateral_offset;
        // (a study places its vehicle itself, on its own track)
        s.initial_state = InitialState::Static;
        let (_, x_max, _) = extent(&s.vehicle);
        let (d, len) = (s.distance(), s.track.length());
        if !(d.is_finite() && s.start + d + x_max <= len) {
            return Err(bad(format!(
                "study of scene '{}': the run covers {d:.1} m from s = {:.2} m, so the leading wheelset ends at s = {:.1} m, beyond the end of track '{}' ({len:.1} m long)",
                self.name,
                s.start,
                s.start + d + x_max,
                s.track_file.display()
            )));
        }
        Ok(s)
    }

    /// Whether degree of freedom `dof` is frozen, by the vehicle file or by the scene.
    pub fn is_frozen(&self, dof: Dof) -> bool {
        !self.vehicle.dofs().contains(&dof) || self.frozen.contains(&dof)
    }

    /// The degrees of freedom the simulation integrates: the vehicle's, less those the scene
    /// freezes (same order as [`VehicleModel::dofs`]).
    pub fn dofs(&self) -> Vec<Dof> {
        let mut d = self.vehicle.dofs();
        d.retain(|x| !self.frozen.contains(x));
        d
    }
}

/// `a/b/../c` → `a/c` (lexically), so that messages name files the way a user would.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

/// The compile pass: one sink for the scene, the other files' problems kept apart.
struct Compiler<'a> {
    sink: Sink<'a>,
    dropped: &'a [(usize, String)],
    unreadable: &'a [String],
    external: Vec<Problem>,
}

fn is_dropped(dropped: &[(usize, String)], table: &Range<usize>, key: &str) -> bool {
    dropped.iter().any(|(s, k)| *s == table.start && k == key)
}

/// Wheelset positions: (leading id, x max, x min) in the vehicle frame.
/// \[1/m\] curvature below which track counts as straight (a radius above 100 km): for the
/// start of a run and for the studies of `crate::stability`.
pub(crate) const STRAIGHT_CURVATURE: f64 = 1e-5;

/// The leading wheelset and the largest and smallest wheelset x in the vehicle frame.
pub(crate) fn extent(vehicle: &VehicleModel) -> (WheelsetId, f64, f64) {
    let ws = vehicle.wheelsets();
    let mut lead = 0;
    for (i, w) in ws.iter().enumerate() {
        if w.position[0] > ws[lead].position[0] {
            lead = i;
        }
    }
    let x_min = ws
        .iter()
        .map(|w| w.position[0])
        .fold(f64::INFINITY, f64::min);
    let id = vehicle.wheelset_id(&ws[lead].name).expect("exists");
    (id, ws[lead].position[0], x_min)
}

impl Compiler<'_> {
    fn err(&mut self, span: &Range<usize>, key: &str, message: String) {
        self.sink.at(Some(span), key, message);
    }

    /// A number in `[lo, hi]` (or `(lo, hi]` when `open_lo`); reports and returns `None`
    /// otherwise.
    fn range(
        &mut self,
        v: &Spanned<f64>,
        key: &str,
        unit: &str,
        (lo, hi): (f64, f64),
        open_lo: bool,
    ) -> Option<f64> {
        let x = *v.get_ref();
        let ok = x.is_finite() && (x > lo || (!open_lo && x == lo)) && x <= hi;
        if ok {
            Some(x)
        } else {
            let lb = if open_lo { "(" } else { "[" };
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" {unit}")
            };
            self.err(
                &v.span(),
                key,
                format!("{key} must lie in {lb}{lo:e}, {hi:e}]{unit}, found {x}"),
            );
            None
        }
    }

    /// `[contact] polach`: each key in its range, then `k_s` ≤ `k_a` (Polach's k_S ≤ k_A ≤ 1).
    fn polach(&mut self, p: &PolachSpec) -> Option<PolachAdhesion> {
        let mut out = PolachAdhesion::default();
        let mut ok = true;
        let mut take = |v: &Option<Spanned<f64>>,
                        key: &str,
                        unit: &str,
                        range: (f64, f64),
                        open_lo: bool,
                        field: &mut f64| {
            if let Some(v) = v {
                match self.range(v, key, unit, range, open_lo) {
                    Some(x) => *field = x,
                    None => ok = false,
                }
            }
        };
        take(&p.k_a, "polach.k_a", "", (0.0, 1.0), true, &mut out.k_a);
        take(&p.k_s, "polach.k_s", "", (0.0, 1.0), true, &mut out.k_s);
        if ok && out.k_s > out.k_a {
            let span = p.k_s.as_ref().or(p.k_a.as_ref()).map(|v| v.span());
            self.sink.at(
                span.as_ref(),
                "polach.k_s",
                format!(
                    "polach.k_s must not exceed polach.k_a (Polach's k_S <= k_A <= 1), found \
                     k_s = {} and k_a = {}",
                    out.k_s, out.k_a
                ),
            );
            return None;
        }
        ok.then_some(out)
    }

    /// `[contact] falling_friction`: each key in its range.
    fn falling_friction(&mut self, f: &FallingFrictionSpec) -> Option<FallingFriction> {
        let mut out = FallingFriction::default();
        let mut ok = true;
        if let Some(v) = &f.ratio_at_infinite_slip {
            match self.range(
                v,
                "falling_friction.ratio_at_infinite_slip",
                "",
                (0.0, 1.0),
                false,
            ) {
                Some(x) => out.ratio = x,
                None => ok = false,
            }
        }
        if let Some(v) = &f.decay_s_per_m {
            match self.range(
                v,
                "falling_friction.decay_s_per_m",
                "s/m",
                (0.0, 100.0),
                false,
            ) {
                Some(x) => out.decay = x,
                None => ok = false,
            }
        }
        ok.then_some(out)
    }

    /// `[contact] friction` (checked by [`FrictionSpec::problem`]).
    fn friction(&mut self, f: &Spanned<FrictionSpec>) -> Option<[Friction; 2]> {
        if let Some(message) = f.get_ref().problem("friction") {
            self.err(&f.span(), "friction", message);
            return None;
        }
        Some([0, 1].map(|k| friction_model(f.get_ref(), k)))
    }

    fn compile(&mut self, spec: &SceneSpec, source_name: &str, base_dir: &Path) -> Option<Scene> {
        let root = 0..0;
        let name = spec
            .name
            .as_ref()
            .map_or_else(|| source_name.to_owned(), |n| n.get_ref().clone());

        let vehicle = self.vehicle(spec, &root, base_dir);
        let track = self.track(spec, &root, base_dir);
        let speed = self.speed(spec, &root);
        let length = self.length(spec, &root);
        let contact = self.contact(spec.contact.as_ref());
        let integrator = self.integrator(spec.integrator.as_ref());
        let log = self.log(spec.log.as_ref());
        let assessment = self.assessment(
            spec.assessment.as_ref(),
            log.as_ref(),
            vehicle.as_ref().map(|v| &v.1),
        );
        let mut start_ok = true;
        let start = spec.start_m.as_ref().and_then(|v| {
            let x = *v.get_ref();
            if !x.is_finite() {
                self.err(
                    &v.span(),
                    "start_m",
                    format!("start_m must be a finite number of m, found {x}"),
                );
                start_ok = false;
            }
            x.is_finite().then_some(x)
        });

        // Checks that need the vehicle and the track.
        let (vehicle_file, vehicle) = vehicle?;
        let (track_file, track, track_spec) = track?;
        let (lead, x_max, x_min) = extent(&vehicle);
        let start = start.unwrap_or_else(|| (-x_min).max(0.0));
        self.curves(spec, &vehicle, &track, &track_spec, &track_file);
        let frozen = self.freeze(spec.freeze.as_ref(), &vehicle);
        let initial = self.initial(spec.initial.as_ref(), &vehicle, lead, &frozen);
        let fits = start_ok
            && self.fits(
                spec,
                &vehicle,
                &track,
                &track_file,
                (start, initial.map_or(InitialState::Static, |i| i.1)),
                (x_max, x_min),
                speed.as_ref(),
                length,
            );
        if !fits {
            return None;
        }
        let (contact, friction, warm_start) = contact?;
        Some(Scene {
            name,
            source: source_name.to_owned(),
            vehicle_file,
            vehicle,
            track_file,
            track,
            speed: speed?,
            start,
            length: length?,
            contact,
            friction,
            warm_start,
            integrator: integrator?,
            log: log?,
            initial: initial?.0,
            initial_state: initial?.1,
            frozen: frozen?,
            assessment: assessment?,
        })
    }

    /// `[assessment]`: α in (0, 1], an instability frequency whose band the log rate carries,
    /// positive limits.
    fn assessment(
        &mut self,
        a: Option<&Spanned<AssessmentSpec>>,
        log: Option<&LogOptions>,
        vehicle: Option<&VehicleModel>,
    ) -> Option<AssessOptions> {
        let mut out = AssessOptions::default();
        let Some(a) = a else {
            return (!self.unreadable.iter().any(|t| t == "assessment")).then_some(out);
        };
        let a = a.get_ref();
        let mut ok = true;
        if let Some(v) = &a.alpha {
            match self.range(v, "alpha", "", (0.0, 1.0), true) {
                Some(x) => out.alpha = x,
                None => ok = false,
            }
        }
        if let Some(v) = &a.rate_hz {
            let log_rate = log.map_or(DEFAULT_LOG_RATE_HZ, |l| l.rate_hz);
            match self.range(v, "rate_hz", "Hz", (0.0, MAX_ASSESSMENT_RATE_HZ), true) {
                Some(f) => {
                    let k = f / log_rate;
                    if k < 1.0 - 1e-9 || (k - k.round()).abs() > 1e-9 * k {
                        self.err(
                            &v.span(),
                            "rate_hz",
                            format!(
                                "[assessment] rate_hz = {f} Hz: expected a whole multiple of the \
                                 log rate, [log] rate_hz = {log_rate} Hz (the log's samples are \
                                 among the assessment's)"
                            ),
                        );
                        ok = false;
                    } else {
                        out.rate_hz = Some(f);
                    }
                }
                None => ok = false,
            }
        }
        if let Some(v) = &a.instability_frequency_hz {
            match self.range(
                v,
                "instability_frequency_hz",
                "Hz",
                (0.0, MAX_INSTABILITY_HZ),
                true,
            ) {
                Some(f) => {
                    let top = stability_band(f).1;
                    // (the band must lie below half the assessment's rate, the log rate's
                    // multiple compiled above; by default at or above 1 kHz for any model)
                    match log.map(|l| out.rate(l.rate_hz, DEFAULT_ASSESSMENT_RATE_HZ)) {
                        Some(rate) if 2.0 * top >= rate => {
                            self.err(
                                &v.span(),
                                "instability_frequency_hz",
                                format!(
                                    "[assessment] instability_frequency_hz = {f} Hz: its band \
                                     reaches {top} Hz (f0 + {STABILITY_HALF_BAND} Hz), which \
                                     needs an assessment rate above {} Hz; the assessment \
                                     samples at {rate} Hz ([assessment] rate_hz, by default the \
                                     log rate's multiple at or above \
                                     {DEFAULT_ASSESSMENT_RATE_HZ} Hz, 2000 Hz for the Hertz \
                                     models)",
                                    2.0 * top,
                                ),
                            );
                            ok = false;
                        }
                        _ => out.instability_frequency = Some(f),
                    }
                }
                None => ok = false,
            }
        }
        let limits = [
            (&a.y_over_q_limit, "y_over_q_limit", "", 1.0, 10.0),
            (
                &a.y_over_q_limit_small_radius,
                "y_over_q_limit_small_radius",
                "",
                1.0,
                10.0,
            ),
            (&a.small_radius_m, "small_radius_m", "m", 1.0, 1e5),
            (&a.q_limit_kn, "q_limit_kn", "kN", 1e3, 1e4),
            (&a.y_qst_limit_kn, "y_qst_limit_kn", "kN", 1e3, 1e4),
            (&a.q_qst_limit_kn, "q_qst_limit_kn", "kN", 1e3, 1e4),
        ];
        let mut values = [None; 6];
        for (value, (v, key, unit, scale, hi)) in values.iter_mut().zip(limits) {
            if let Some(v) = v {
                match self.range(v, key, unit, (0.0, hi), true) {
                    Some(x) => *value = Some(scale * x),
                    None => ok = false,
                }
            }
        }
        let l = &mut out.limits;
        let [yq, yq_small, small, q, y_qst, q_qst] = values;
        l.y_over_q = yq.unwrap_or(l.y_over_q);
        l.y_over_q_small_radius = yq_small.unwrap_or(l.y_over_q_small_radius);
        l.small_radius = small.unwrap_or(l.small_radius);
        l.q = q.or(l.q);
        l.y_qst = y_qst.unwrap_or(l.y_qst);
        l.q_qst = q_qst.unwrap_or(l.q_qst);
        if let Some(w) = &a.vertical_weighting {
            let name = w.get_ref().trim();
            match VerticalWeighting::from_name(name) {
                Some(k) => out.vertical_weighting = k,
                None => {
                    self.err(
                        &w.span(),
                        "vertical_weighting",
                        format!(
                            "[assessment] vertical_weighting: unknown weighting '{name}'{}; \
                             expected one of: {}",
                            did_you_mean(name, VerticalWeighting::NAMES.into_iter()),
                            VerticalWeighting::NAMES.join(", ")
                        ),
                    );
                    ok = false;
                }
            }
        }
        match (&a.section_length_m, &a.section_k) {
            (Some(l), k) => {
                let length = self.range(l, "section_length_m", "m", SECTION_LENGTH_RANGE, false);
                // (outer None: a bad k; inner None: no k)
                let k = match k {
                    Some(k) => self.range(k, "section_k", "", (0.0, 10.0), true).map(Some),
                    None => Some(None),
                };
                match (length, k) {
                    (Some(length), Some(k)) => out.sections = Some(SectionOptions { length, k }),
                    _ => ok = false,
                }
            }
            (None, Some(k)) => {
                self.err(
                    &k.span(),
                    "section_k",
                    "[assessment] section_k: expected section_length_m beside it (k weighs the \
                     spread of the per-section statistics), found none"
                        .into(),
                );
                ok = false;
            }
            (None, None) => {}
        }
        if let Some(points) = &a.comfort_points {
            if vehicle.is_some_and(|v| v.bodies().is_empty()) {
                self.err(
                    &points.span(),
                    "comfort_points",
                    "[assessment] comfort_points: the vehicle has no rigid body (carbody) to \
                     carry them"
                        .into(),
                );
                ok = false;
            }
            for p in points.get_ref() {
                let p = p.get_ref();
                let name = p.name.get_ref().trim().to_owned();
                if name.is_empty() || out.comfort_points.iter().any(|q| q.name == name) {
                    self.err(
                        &p.name.span(),
                        "name",
                        format!(
                            "[assessment] comfort point name '{name}': expected a non-empty \
                             name used once"
                        ),
                    );
                    ok = false;
                }
                let mut offset = [0.0; 3];
                for (k, (v, key)) in [(&p.x_m, "x_m"), (&p.y_m, "y_m"), (&p.z_m, "z_m")]
                    .into_iter()
                    .enumerate()
                {
                    if let Some(v) = v {
                        match self.range(
                            v,
                            key,
                            "m",
                            (-MAX_COMFORT_OFFSET, MAX_COMFORT_OFFSET),
                            false,
                        ) {
                            Some(x) => offset[k] = x,
                            None => ok = false,
                        }
                    }
                }
                out.comfort_points.push(ComfortPoint { name, offset });
            }
        }
        ok.then_some(out)
    }

    fn path_key(
        &mut self,
        v: &Option<Spanned<String>>,
        root: &Range<usize>,
        key: &str,
        what: &str,
        base_dir: &Path,
    ) -> Option<(PathBuf, Range<usize>)> {
        let Some(v) = v else {
            if !is_dropped(self.dropped, root, key) {
                self.err(
                    root,
                    key,
                    format!("missing key '{key}' (expected the path of a {what} file, relative to the scene file)"),
                );
            }
            return None;
        };
        let s = v.get_ref().trim();
        if s.is_empty() {
            self.err(
                &v.span(),
                key,
                format!("{key} is empty (expected the path of a {what} file)"),
            );
            return None;
        }
        Some((normalize(&base_dir.join(s)), v.span()))
    }

    fn vehicle(
        &mut self,
        spec: &SceneSpec,
        root: &Range<usize>,
        base_dir: &Path,
    ) -> Option<(PathBuf, VehicleModel)> {
        let (path, span) = self.path_key(&spec.vehicle, root, "vehicle", "vehicle", base_dir)?;
        let file = path.display().to_string();
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) => {
                self.err(
                    &span,
                    "vehicle",
                    format!("vehicle: cannot read vehicle file '{file}': {e}"),
                );
                return None;
            }
        };
        let dir = path.parent().unwrap_or(Path::new("."));
        match VehicleModel::from_toml_str(&text, &file, dir) {
            Ok(v) => Some((path, v)),
            Err(VehicleError::Invalid { problems }) => {
                self.err(
                    &span,
                    "vehicle",
                    format!(
                        "vehicle: vehicle file '{file}' has {} problem(s), listed below",
                        problems.len()
                    ),
                );
                self.external.extend(problems.into_iter().map(|p| Problem {
                    file: p.file,
                    line: p.line,
                    col: p.col,
                    key: p.key,
                    message: p.message,
                }));
                None
            }
            Err(e) => {
                self.err(&span, "vehicle", format!("vehicle: {e}"));
                None
            }
        }
    }

    fn track(
        &mut self,
        spec: &SceneSpec,
        root: &Range<usize>,
        base_dir: &Path,
    ) -> Option<(PathBuf, TrackModel, TrackSpec)> {
        let (path, span) = self.path_key(&spec.track, root, "track", "track", base_dir)?;
        let file = path.display().to_string();
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) => {
                self.err(
                    &span,
                    "track",
                    format!("track: cannot read track file '{file}': {e}"),
                );
                return None;
            }
        };
        let result = TrackSpec::from_toml_str(&text, &file)
            .and_then(|s| TrackModel::compile(&s, &file).map(|m| (m, s)));
        match result {
            Ok((model, s)) => Some((path, model, s)),
            Err(errors) => {
                let mut located = 0;
                for e in errors.errors {
                    match e {
                        TrackError::Parse {
                            file,
                            line,
                            col,
                            message,
                        } => {
                            located += 1;
                            self.external.push(Problem {
                                file,
                                line,
                                col,
                                key: String::new(),
                                message,
                            });
                        }
                        TrackError::Invalid {
                            file,
                            line,
                            col,
                            key,
                            message,
                        } => {
                            located += 1;
                            self.external.push(Problem {
                                file,
                                line,
                                col,
                                key,
                                message,
                            });
                        }
                        other => self.err(&span, "track", format!("track: {other}")),
                    }
                }
                if located > 0 {
                    self.err(
                        &span,
                        "track",
                        format!(
                            "track: track file '{file}' has {located} problem(s), listed below"
                        ),
                    );
                }
                None
            }
        }
    }

    fn speed(&mut self, spec: &SceneSpec, root: &Range<usize>) -> Option<SpeedProfile> {
        let (lo, hi) = (MIN_SPEED_KMH, MAX_SPEED_KMH);
        match (&spec.speed_kmh, &spec.speed_profile) {
            (Some(v), Some(p)) => {
                self.err(
                    &v.span().min_by_start(&p.span()),
                    "speed_kmh",
                    "give either speed_kmh (constant) or [speed_profile], not both".to_owned(),
                );
                None
            }
            (Some(v), None) => {
                let x = *v.get_ref();
                if x.is_finite() && x >= lo && x <= hi {
                    Some(SpeedProfile::constant(x / 3.6))
                } else {
                    self.err(
                        &v.span(),
                        "speed_kmh",
                        format!(
                            "speed_kmh must be a speed from {lo} to {hi} km/h, found {}",
                            short_number(x)
                        ),
                    );
                    None
                }
            }
            (None, Some(p)) => self.profile(p),
            (None, None) => {
                if !is_dropped(self.dropped, root, "speed_kmh")
                    && !self.unreadable.iter().any(|t| t == "speed_profile")
                {
                    self.err(
                        root,
                        "speed_kmh",
                        "missing speed: give speed_kmh (km/h, constant) or a [speed_profile] table"
                            .to_owned(),
                    );
                }
                None
            }
        }
    }

    fn profile(&mut self, p: &Spanned<SpeedProfileSpec>) -> Option<SpeedProfile> {
        let table = p.span();
        let s = p.get_ref();
        let missing = |c: &mut Self, key: &str, v: bool| {
            if !v && !is_dropped(c.dropped, &table, key) {
                c.err(
                    &table,
                    key,
                    format!("[speed_profile] missing key '{key}' (expected an array of numbers)"),
                );
            }
        };
        missing(self, "distance_m", s.distance_m.is_some());
        missing(self, "speed_kmh", s.speed_kmh.is_some());
        let (d, v) = (s.distance_m.as_ref()?, s.speed_kmh.as_ref()?);
        let mut ok = true;
        if d.get_ref().len() < 2 {
            self.err(
                &d.span(),
                "distance_m",
                format!(
                    "[speed_profile] distance_m needs at least 2 points, found {} (use speed_kmh for a constant speed)",
                    d.get_ref().len()
                ),
            );
            ok = false;
        }
        if d.get_ref().len() != v.get_ref().len() {
            self.err(
                &v.span(),
                "speed_kmh",
                format!(
                    "[speed_profile] speed_kmh has {} values but distance_m has {}; expected one speed per distance",
                    v.get_ref().len(),
                    d.get_ref().len()
                ),
            );
            ok = false;
        }
        if let Some(first) = d.get_ref().first()
            && *first.get_ref() != 0.0
        {
            self.err(
                &first.span(),
                "distance_m",
                format!(
                    "[speed_profile] distance_m must start at 0 (the start of the run), found {}",
                    first.get_ref()
                ),
            );
            ok = false;
        }
        for w in d.get_ref().windows(2) {
            let (a, b) = (*w[0].get_ref(), *w[1].get_ref());
            if !(b.is_finite() && b > a) {
                self.err(
                    &w[1].span(),
                    "distance_m",
                    format!("[speed_profile] distance_m must be strictly increasing, but {b} follows {a}"),
                );
                ok = false;
            }
        }
        for x in v.get_ref() {
            let y = *x.get_ref();
            if !(y.is_finite() && (MIN_SPEED_KMH..=MAX_SPEED_KMH).contains(&y)) {
                self.err(
                    &x.span(),
                    "speed_kmh",
                    format!("[speed_profile] speed_kmh values must be speeds from {MIN_SPEED_KMH} to {MAX_SPEED_KMH} km/h, found {}", short_number(y)),
                );
                ok = false;
            }
        }
        if !ok {
            return None;
        }
        SpeedProfile::from_points(
            d.get_ref().iter().map(|x| *x.get_ref()).collect(),
            v.get_ref().iter().map(|x| *x.get_ref() / 3.6).collect(),
        )
    }

    fn length(&mut self, spec: &SceneSpec, root: &Range<usize>) -> Option<RunLength> {
        match (&spec.duration_s, &spec.distance_m) {
            (Some(t), Some(d)) => {
                let later = if t.span().start > d.span().start {
                    (t.span(), "duration_s")
                } else {
                    (d.span(), "distance_m")
                };
                self.err(
                    &later.0,
                    later.1,
                    "give either duration_s or distance_m, not both".to_owned(),
                );
                None
            }
            (Some(t), None) => {
                let x = *t.get_ref();
                if x.is_finite() && x > 0.0 && x <= MAX_DURATION_S {
                    Some(RunLength::Duration(x))
                } else {
                    self.err(
                        &t.span(),
                        "duration_s",
                        format!("duration_s must be a positive time of at most {MAX_DURATION_S} s, found {x}"),
                    );
                    None
                }
            }
            (None, Some(d)) => {
                let x = *d.get_ref();
                if x.is_finite() && x > 0.0 {
                    Some(RunLength::Distance(x))
                } else {
                    self.err(
                        &d.span(),
                        "distance_m",
                        format!("distance_m must be a positive distance in m, found {x}"),
                    );
                    None
                }
            }
            (None, None) => {
                if !is_dropped(self.dropped, root, "duration_s")
                    && !is_dropped(self.dropped, root, "distance_m")
                {
                    self.err(
                        root,
                        "duration_s",
                        "missing run length: give duration_s (s) or distance_m (m)".to_owned(),
                    );
                }
                None
            }
        }
    }

    fn contact(
        &mut self,
        c: Option<&Spanned<ContactSpec>>,
    ) -> Option<(ContactOptions, [Friction; 2], bool)> {
        let mut opts = ContactOptions::default();
        let Some(c) = c else {
            return (!self.unreadable.iter().any(|t| t == "contact")).then_some((
                opts,
                default_friction(),
                true,
            ));
        };
        let c = c.get_ref();
        let mut ok = true;
        if let Some(m) = &c.model {
            let name = m.get_ref().trim();
            match ContactModelKind::ALL.into_iter().find(|k| k.name() == name) {
                Some(k) => opts.model = k,
                None => {
                    let names: Vec<&str> = ContactModelKind::ALL.iter().map(|k| k.name()).collect();
                    self.err(
                        &m.span(),
                        "contact.model",
                        format!(
                            "[contact] model: unknown contact model '{name}'{}; expected one of: {}",
                            did_you_mean(name, names.iter().copied()),
                            names.join(", ")
                        ),
                    );
                    ok = false;
                }
            }
        }
        if let Some(s) = &c.step_mm {
            match self.range(s, "step_mm", "mm", CONTACT_STEP_RANGE_MM, false) {
                Some(x) => opts.travel.step = x * 1e-3,
                None => ok = false,
            }
        }
        let mut friction = default_friction();
        if let Some(f) = &c.friction {
            match self.friction(f) {
                Some(x) => friction = x,
                None => ok = false,
            }
        }
        if let Some(f) = &c.creep_coefficient_n {
            if opts.model != ContactModelKind::Linear {
                self.err(
                    &f.span(),
                    "contact.creep_coefficient_n",
                    format!(
                        "[contact] creep_coefficient_n applies only to model = \"linear\", found model = \"{}\"",
                        opts.model.name()
                    ),
                );
                ok = false;
            } else {
                match self.range(
                    f,
                    "creep_coefficient_n",
                    "N",
                    CREEP_COEFFICIENT_RANGE_N,
                    false,
                ) {
                    Some(x) => opts.linear_creep = Some(x),
                    None => ok = false,
                }
            }
        }
        if let Some(p) = &c.polach {
            if opts.model != ContactModelKind::Polach {
                self.err(
                    &p.span(),
                    "contact.polach",
                    format!(
                        "[contact] polach applies only to model = \"polach\", found model = \"{}\"",
                        opts.model.name()
                    ),
                );
                ok = false;
            } else {
                match self.polach(p.get_ref()) {
                    Some(x) => opts.polach = x,
                    None => ok = false,
                }
            }
        }
        if let Some(f) = &c.falling_friction {
            if matches!(
                opts.model,
                ContactModelKind::Linear | ContactModelKind::Halfspace
            ) {
                self.err(
                    &f.span(),
                    "contact.falling_friction",
                    format!(
                        "[contact] falling_friction applies to model = \"polach\", \"fastsim\" or \"stripes\", found model = \"{}\" ({})",
                        opts.model.name(),
                        if opts.model == ContactModelKind::Linear {
                            "which has no friction"
                        } else {
                            "a reference level, with Coulomb friction"
                        }
                    ),
                );
                ok = false;
            } else {
                match self.falling_friction(f.get_ref()) {
                    Some(x) => opts.falling_friction = x,
                    None => ok = false,
                }
            }
        }
        if let Some(h) = &c.hertz_search {
            let name = h.get_ref().trim();
            match HertzSearch::from_name(name) {
                Ok(k) => opts.hertz_search = k,
                Err(_) => {
                    self.err(
                        &h.span(),
                        "contact.hertz_search",
                        format!(
                            "[contact] hertz_search: unknown search '{name}'{}; expected one of: \
                             point, travel",
                            did_you_mean(name, ["point", "travel"].into_iter())
                        ),
                    );
                    ok = false;
                }
            }
        }
        if let Some(t) = &c.tangential {
            let name = t.get_ref().trim();
            let strip_model = matches!(
                opts.model,
                ContactModelKind::Stripes | ContactModelKind::Halfspace
            );
            let found = match name {
                "fastrip" => Some(Tangential::Fastrip),
                "fastsim" => Some(Tangential::Fastsim),
                _ => None,
            };
            let problem = match found {
                _ if !strip_model => Some(format!(
                    "[contact] tangential applies only to model = \"stripes\" or \"halfspace\" (the Hertz models have their own), found model = \"{}\"",
                    opts.model.name()
                )),
                Some(k) => {
                    opts.tangential = k;
                    None
                }
                None if name == "exact" => Some(
                    "[contact] tangential = \"exact\" (Kalker's exact solution, about 10 ms per wheel evaluation) is the reference level of `railsim contact`, not for dynamics; expected one of: fastrip, fastsim".to_owned(),
                ),
                None => Some(format!(
                    "[contact] tangential: unknown solution '{name}'{}; expected one of: fastrip, fastsim",
                    did_you_mean(name, ["fastrip", "fastsim"].into_iter())
                )),
            };
            if let Some(m) = problem {
                self.err(&t.span(), "contact.tangential", m);
                ok = false;
            }
        }
        let warm_start = c.warm_start.as_ref().is_none_or(|w| *w.get_ref());
        ok.then_some((opts, friction, warm_start))
    }

    fn integrator(&mut self, i: Option<&Spanned<IntegratorSpec>>) -> Option<Method> {
        let Some(i) = i else {
            return (!self.unreadable.iter().any(|t| t == "integrator"))
                .then_some(Method::dormand_prince(DEFAULT_RTOL, DEFAULT_ATOL));
        };
        let table = i.span();
        let i = i.get_ref();
        let Some(m) = &i.method else {
            if !is_dropped(self.dropped, &table, "method") {
                self.err(
                    &table,
                    "method",
                    format!(
                        "[integrator] missing key 'method' (expected one of: {})",
                        INTEGRATOR_NAMES.join(", ")
                    ),
                );
            }
            return None;
        };
        let name = m.get_ref().trim();
        let not_for = |c: &mut Self, v: &Option<Spanned<f64>>, key: &str, takes: &str| {
            if let Some(v) = v {
                c.err(
                    &v.span(),
                    key,
                    format!("[integrator] key '{key}' does not apply to method '{name}' (it takes: {takes})"),
                );
            }
        };
        match name {
            "rk4" => {
                not_for(self, &i.rtol, "rtol", "step_s");
                not_for(self, &i.atol, "atol", "step_s");
                not_for(self, &i.max_step_s, "max_step_s", "step_s");
                let Some(h) = &i.step_s else {
                    if !is_dropped(self.dropped, &table, "step_s") {
                        self.err(
                            &m.span(),
                            "step_s",
                            format!(
                                "[integrator] method 'rk4' needs step_s, its fixed step in s (in [{:e}, {:e}])",
                                STEP_RANGE_S.0, STEP_RANGE_S.1
                            ),
                        );
                    }
                    return None;
                };
                let h = self.range(h, "step_s", "s", STEP_RANGE_S, false)?;
                let bad = [&i.rtol, &i.atol, &i.max_step_s]
                    .iter()
                    .any(|v| v.is_some());
                (!bad).then_some(Method::Rk4 { h })
            }
            "dopri5" | "bs3" | "radau5" => {
                let takes = "rtol, atol, max_step_s";
                not_for(self, &i.step_s, "step_s", takes);
                let rtol = match &i.rtol {
                    None => Some(DEFAULT_RTOL),
                    Some(v) => self.range(v, "rtol", "(relative)", RTOL_RANGE, false),
                };
                let atol = match &i.atol {
                    None => Some(DEFAULT_ATOL),
                    Some(v) => self.range(v, "atol", "(SI units of the state)", ATOL_RANGE, false),
                };
                let h_max = match &i.max_step_s {
                    None => Some(f64::INFINITY),
                    Some(v) => self.range(
                        v,
                        "max_step_s",
                        "s",
                        (MIN_MAX_STEP_S, MAX_STEP_LIMIT_S),
                        false,
                    ),
                };
                let (rtol, atol, h_max) = (rtol?, atol?, h_max?);
                if i.step_s.is_some() {
                    return None;
                }
                Some(if name == "dopri5" {
                    Method::DormandPrince {
                        rtol,
                        atol,
                        h0: None,
                        h_max,
                    }
                } else if name == "bs3" {
                    Method::AdaptiveExplicit {
                        tableau: &railsim_ode::tableau::BS3,
                        rtol,
                        atol,
                        h0: None,
                        h_max,
                    }
                } else {
                    match Method::radau5(rtol, atol) {
                        Method::Radau5 {
                            rtol,
                            atol,
                            h0,
                            jacobian_reuse,
                            ..
                        } => Method::Radau5 {
                            rtol,
                            atol,
                            h0,
                            h_max,
                            jacobian_reuse,
                        },
                        other => other,
                    }
                })
            }
            _ => {
                self.err(
                    &m.span(),
                    "integrator.method",
                    format!(
                        "[integrator] method: unknown integrator '{name}'{}; expected one of: {}",
                        did_you_mean(name, INTEGRATOR_NAMES),
                        INTEGRATOR_NAMES.join(", ")
                    ),
                );
                None
            }
        }
    }

    fn log(&mut self, l: Option<&Spanned<LogSpec>>) -> Option<LogOptions> {
        let mut opts = LogOptions {
            path: PathBuf::from(DEFAULT_LOG_PATH),
            rate_hz: DEFAULT_LOG_RATE_HZ,
            topics: Topic::DEFAULT.to_vec(),
        };
        let Some(l) = l else {
            return (!self.unreadable.iter().any(|t| t == "log")).then_some(opts);
        };
        let l = l.get_ref();
        let mut ok = true;
        if let Some(p) = &l.path {
            let s = p.get_ref().trim();
            if s.is_empty() || !s.ends_with(".mcap") {
                self.err(
                    &p.span(),
                    "path",
                    format!("[log] path must name an MCAP file ending in '.mcap', found '{s}'"),
                );
                ok = false;
            } else {
                opts.path = PathBuf::from(s);
            }
        }
        if let Some(r) = &l.rate_hz {
            match self.range(r, "rate_hz", "Hz", (0.0, MAX_LOG_RATE_HZ), true) {
                Some(x) => opts.rate_hz = x,
                None => ok = false,
            }
        }
        if let Some(t) = &l.topics {
            let names: Vec<&str> = Topic::ALL.iter().map(|t| t.name()).collect();
            if t.get_ref().is_empty() {
                self.err(
                    &t.span(),
                    "topics",
                    format!(
                        "[log] topics is empty; expected some of: {}",
                        names.join(", ")
                    ),
                );
                ok = false;
            }
            let mut topics = Vec::new();
            for item in t.get_ref() {
                let s = item.get_ref().trim();
                match Topic::ALL.into_iter().find(|x| x.name() == s) {
                    Some(x) if topics.contains(&x) => {
                        self.err(
                            &item.span(),
                            "topics",
                            format!("[log] topics: '{s}' is listed twice"),
                        );
                        ok = false;
                    }
                    Some(x) => topics.push(x),
                    None => {
                        self.err(
                            &item.span(),
                            "topics",
                            format!(
                                "[log] topics: unknown topic '{s}'{}; expected some of: {}",
                                did_you_mean(s, names.iter().copied()),
                                names.join(", ")
                            ),
                        );
                        ok = false;
                    }
                }
            }
            opts.topics = topics;
        }
        ok.then_some(opts)
    }

    /// Reject a track whose tightest curve is tighter than the vehicle's rigid wheelbase allows.
    fn curves(
        &mut self,
        spec: &SceneSpec,
        vehicle: &VehicleModel,
        track: &TrackModel,
        track_spec: &TrackSpec,
        track_file: &Path,
    ) {
        let Some(wb) = longest_rigid_wheelbase(vehicle) else {
            return;
        };
        let required = RADIUS_PER_WHEELBASE * wb.length;
        let mut tightest: Option<(usize, f64)> = None;
        for (i, s) in track.segments().iter().enumerate() {
            let k = s.curvature_start.abs().max(s.curvature_end.abs());
            if k > 0.0 && 1.0 / k < required && tightest.is_none_or(|(_, kt)| k > kt) {
                tightest = Some((i, k));
            }
        }
        let Some((i, k)) = tightest else {
            return;
        };
        let seg = &track.segments()[i];
        let what = match seg.kind {
            SegmentKind::Curve => "curve",
            SegmentKind::Transition(_) => "transition",
            SegmentKind::Tangent => "segment",
        };
        let place = match track_spec
            .segment
            .get(i)
            .filter(|_| track_spec.segment.len() == track.segments().len())
        {
            Some(s) => {
                let span = s
                    .get_ref()
                    .radius_m
                    .as_ref()
                    .map_or_else(|| s.span(), |r| r.span());
                let (line, col) = track_spec.source.line_col(span.start);
                format!("{}:{line}:{col}", track_file.display())
            }
            None => track_file.display().to_string(),
        };
        let span = spec.track.as_ref().map_or(0..0, |t| t.span());
        self.err(
            &span,
            "track",
            format!(
                "track: the {what} of radius {:.1} m starting at s = {:.1} m ({place}) is too tight for vehicle '{}': \
                 its longest rigid wheelbase is {:.2} m (wheelsets '{}' and '{}'), and a rigid wheelbase a needs \
                 R >= {RADIUS_PER_WHEELBASE}·a = {:.1} m (angle of attack a/(2R) <= 25 mrad)",
                1.0 / k,
                seg.s_start,
                vehicle.name(),
                wb.length,
                vehicle.wheelset(wb.front).name,
                vehicle.wheelset(wb.rear).name,
                required
            ),
        );
    }

    fn freeze(
        &mut self,
        f: Option<&Spanned<Vec<Spanned<String>>>>,
        vehicle: &VehicleModel,
    ) -> Option<Vec<Dof>> {
        let Some(f) = f else {
            return Some(Vec::new());
        };
        let mut members: Vec<(String, Member)> = Vec::new();
        for b in vehicle.bodies() {
            members.push((
                b.name.clone(),
                Member::Body(vehicle.body_id(&b.name).expect("exists")),
            ));
        }
        for w in vehicle.wheelsets() {
            members.push((
                w.name.clone(),
                Member::Wheelset(vehicle.wheelset_id(&w.name).expect("exists")),
            ));
        }
        let dof_name = |m: Member, k: DofKind| match m {
            Member::Body(_) => k.body_name(),
            Member::Wheelset(_) => k.wheelset_name(),
        };
        let all: Vec<String> = members
            .iter()
            .flat_map(|(n, m)| {
                DofKind::ALL
                    .iter()
                    .map(move |k| format!("{n}.{}", dof_name(*m, *k)))
            })
            .collect();
        let mut out = Vec::new();
        let mut ok = true;
        for item in f.get_ref() {
            let s = item.get_ref().trim();
            let span = item.span();
            let Some((body, dof)) = s.rsplit_once('.') else {
                self.err(
                    &span,
                    "freeze",
                    format!(
                        "freeze: '{s}' is not a degree of freedom{}; expected \"body.dof\", e.g. \"{}\"",
                        did_you_mean(s, all.iter().map(String::as_str)),
                        all.first().map_or("ws.spin", String::as_str)
                    ),
                );
                ok = false;
                continue;
            };
            let Some((_, m)) = members.iter().find(|(n, _)| n == body) else {
                let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
                self.err(
                    &span,
                    "freeze",
                    format!(
                        "freeze: '{s}': vehicle '{}' has no body or wheelset '{body}'{}; it has: {}",
                        vehicle.name(),
                        did_you_mean(body, names.iter().copied()),
                        names.join(", ")
                    ),
                );
                ok = false;
                continue;
            };
            let m = *m;
            let Some(kind) = DofKind::ALL.into_iter().find(|k| dof_name(m, *k) == dof) else {
                let names: Vec<&str> = DofKind::ALL.iter().map(|k| dof_name(m, *k)).collect();
                let what = if matches!(m, Member::Wheelset(_)) {
                    "wheelset"
                } else {
                    "body"
                };
                self.err(
                    &span,
                    "freeze",
                    format!(
                        "freeze: '{s}': '{dof}' is not a degree of freedom of {what} '{body}'{}; expected one of: {}",
                        did_you_mean(dof, names.iter().copied()),
                        names.join(", ")
                    ),
                );
                ok = false;
                continue;
            };
            let d = Dof { member: m, kind };
            if out.contains(&d) {
                self.err(&span, "freeze", format!("freeze: '{s}' is listed twice"));
                ok = false;
                continue;
            }
            out.push(d);
        }
        if ok && vehicle.dofs().iter().all(|d| out.contains(d)) {
            self.err(
                &f.span(),
                "freeze",
                format!(
                    "freeze: every degree of freedom of vehicle '{}' the vehicle file leaves free is frozen, so nothing would move; expected at least one free",
                    vehicle.name()
                ),
            );
            ok = false;
        }
        ok.then_some(out)
    }

    fn initial(
        &mut self,
        i: Option<&Spanned<InitialSpec>>,
        vehicle: &VehicleModel,
        lead: WheelsetId,
        frozen: &Option<Vec<Dof>>,
    ) -> Option<(InitialDisturbance, InitialState)> {
        let mut out = InitialDisturbance {
            wheelset: lead,
            lateral_offset: 0.0,
            yaw: 0.0,
        };
        let mut state = InitialState::Static;
        let Some(i) = i else {
            return (!self.unreadable.iter().any(|t| t == "initial")).then_some((out, state));
        };
        let i = i.get_ref();
        let mut ok = true;
        if let Some(v) = &i.state {
            let name = v.get_ref().trim();
            match InitialState::ALL.into_iter().find(|k| k.name() == name) {
                Some(k) => state = k,
                None => {
                    self.err(
                        &v.span(),
                        "initial.state",
                        format!(
                            "[initial] state: unknown initial state '{name}'{}; expected one of: {}",
                            did_you_mean(name, InitialState::ALL.into_iter().map(InitialState::name)),
                            InitialState::ALL.map(InitialState::name).join(", ")
                        ),
                    );
                    ok = false;
                }
            }
        }
        let ws = vehicle.wheelset(lead);
        let checks: [Check<'_>; 2] = [
            (
                &i.lateral_offset_mm,
                "lateral_offset_mm",
                "mm",
                MAX_INITIAL_OFFSET_MM,
                DofKind::Y,
                1e-3,
            ),
            (
                &i.yaw_mrad,
                "yaw_mrad",
                "mrad",
                MAX_INITIAL_YAW_MRAD,
                DofKind::Yaw,
                1e-3,
            ),
        ];
        for (v, key, unit, max, kind, scale) in checks {
            let Some(v) = v else { continue };
            let x = *v.get_ref();
            if !(x.is_finite() && x.abs() <= max) {
                self.err(
                    &v.span(),
                    key,
                    format!("[initial] {key} must lie in [-{max}, {max}] {unit}, found {x}"),
                );
                ok = false;
                continue;
            }
            let dof = Dof {
                member: Member::Wheelset(lead),
                kind,
            };
            let by_vehicle = ws.frozen[kind.index()];
            let by_scene = frozen.as_ref().is_some_and(|f| f.contains(&dof));
            if x != 0.0 && (by_vehicle || by_scene) {
                let by = if by_vehicle {
                    "the vehicle file"
                } else {
                    "freeze"
                };
                self.err(
                    &v.span(),
                    key,
                    format!(
                        "[initial] {key}: the leading wheelset '{}' has '{}' frozen (by {by}); a disturbance of a frozen degree of freedom has no effect",
                        ws.name,
                        kind.wheelset_name()
                    ),
                );
                ok = false;
                continue;
            }
            match kind {
                DofKind::Y => out.lateral_offset = x * scale,
                _ => out.yaw = x * scale,
            }
        }
        ok.then_some((out, state))
    }

    /// Check that every wheelset stays on the track from start to end. Returns whether it does.
    fn fits(
        &mut self,
        spec: &SceneSpec,
        vehicle: &VehicleModel,
        track: &TrackModel,
        track_file: &Path,
        (start, state): (f64, InitialState),
        (x_max, x_min): (f64, f64),
        speed: Option<&SpeedProfile>,
        length: Option<RunLength>,
    ) -> bool {
        let len = track.length();
        let mut ok = true;
        let start_span = spec.start_m.as_ref().map_or(0..0, |s| s.span());
        if start + x_min < 0.0 || start + x_max > len {
            self.err(
                &start_span,
                "start_m",
                format!(
                    "start_m = {} m puts the wheelsets of vehicle '{}' at s = {:.2} .. {:.2} m, outside track '{}' (0 .. {len} m)",
                    short_number(start),
                    vehicle.name(),
                    start + x_min,
                    start + x_max,
                    track_file.display()
                ),
            );
            ok = false;
        }
        // The initial state is the static equilibrium on straight level track (docs/models/
        // dynamics.md): every member is placed on its own track-following frame's centre line.
        // Inside a curve the bodies' attachment points then miss each other by the curve's
        // versines (0.30 m between a carbody and its bogies 19 m apart at R = 150 m) and the
        // wheel loads ignore the cant: the Manchester vehicle started in the R = 150 m curve
        // "derailed" at t = 0.03 s. So a start must find the vehicle on straight track without
        // cant. The quasi-static start (`InitialState::QuasiStatic`) solves for the steady state
        // instead, which needs curvature and cant constant under the vehicle (below).
        if ok && state == InitialState::Static {
            let (a, b) = (start + x_min, start + x_max);
            // (radius above 100 km and cant below 0.02 mm count as straight and level)
            let bent_at = |s: f64| {
                let f = track.frame_at(s);
                (f.curvature.abs() > STRAIGHT_CURVATURE || f.roll.abs() > 1e-5).then_some(f)
            };
            let bent = span_points(a, b).find_map(|s| bent_at(s).map(|f| (s, f)));
            if let Some((s_bent, f)) = bent {
                let what = if f.curvature.abs() > STRAIGHT_CURVATURE {
                    format!("radius {:.0} m", 1.0 / f.curvature.abs())
                } else {
                    format!("cant {:.1} mm", f.cant.abs() * 1e3)
                };
                // where the straight level track before it ends
                let mut s_free = s_bent;
                while s_free > 0.0 && bent_at(s_free).is_some() {
                    s_free -= 0.25;
                }
                let advice = if s_free > 0.0 && s_free - (b - a) >= 0.0 {
                    format!("start_m at most {:.2} m", s_free - (b - start))
                } else {
                    "a track with a straight level part before the curve".to_owned()
                };
                self.err(
                    &start_span,
                    "start_m",
                    format!(
                        "start_m = {start} m puts the wheelsets of vehicle '{}' at s = {a:.2} .. {b:.2} m, on curved \
                         or canted track ({what} at s = {s_bent:.2} m); the initial state is the static equilibrium on \
                         straight level track, so the vehicle must start on a tangent without cant and run into the \
                         curve: expected {advice} (or [initial] state = \"quasi-static\" for a start inside a circular curve)",
                        vehicle.name(),
                    ),
                );
                ok = false;
            }
        }
        // A steady state needs the vehicle where the track does not change along it: curvature
        // and cant constant from its rearmost to its leading wheelset (to 1e-5 1/m, the
        // straight limit, and 0.02 mm), so not on a transition.
        if ok && state == InitialState::QuasiStatic {
            let (a, b) = (start + x_min, start + x_max);
            let f0 = track.frame_at(a);
            let changed = span_points(a, b).skip(1).find(|&s| {
                let f = track.frame_at(s);
                (f.curvature - f0.curvature).abs() > STRAIGHT_CURVATURE
                    || (f.cant - f0.cant).abs() > 0.02e-3
            });
            if let Some(s_changed) = changed {
                let f = track.frame_at(s_changed);
                self.err(
                    &start_span,
                    "start_m",
                    format!(
                        "start_m = {start} m puts the wheelsets of vehicle '{}' at s = {a:.2} .. {b:.2} m, where the track \
                         changes (curvature {:.6} 1/m and cant {:.1} mm at s = {a:.2} m, {:.6} 1/m and {:.1} mm at \
                         s = {s_changed:.2} m); the quasi-static start is a steady state, which needs curvature and cant \
                         constant under the vehicle: expected a start with every wheelset on one tangent or in one \
                         circular curve",
                        vehicle.name(),
                        f0.curvature,
                        f0.cant * 1e3,
                        f.curvature,
                        f.cant * 1e3,
                    ),
                );
                ok = false;
            }
        }
        // The initial state takes each wheelset on the rails of its section; in a rail
        // transition the dynamics blend two rails' forces, which it does not.
        if ok {
            let (a, b) = (start + x_min, start + x_max);
            let over = track
                .rail_sections()
                .iter()
                .find(|r| r.transition > 0.0 && r.start < b && r.start + r.transition > a);
            if let Some(r) = over {
                self.err(
                    &start_span,
                    "start_m",
                    format!(
                        "start_m = {start} m puts the wheelsets of vehicle '{}' at s = {a:.2} .. {b:.2} m, over the rail \
                         transition at s = {:.2} .. {:.2} m; the initial state is an equilibrium on one rail \
                         section: expected a start with every wheelset before or after the transition",
                        vehicle.name(),
                        r.start,
                        r.start + r.transition
                    ),
                );
                ok = false;
            }
        }
        let d = match (length, speed) {
            (Some(RunLength::Distance(d)), _) => d,
            (Some(RunLength::Duration(t)), Some(p)) => p.distance_at(t),
            _ => return ok,
        };
        let lead_end = start + d + x_max;
        if ok && lead_end > len {
            let (key, span) = match (&spec.duration_s, &spec.distance_m) {
                (Some(t), _) => ("duration_s", t.span()),
                (_, Some(d)) => ("distance_m", d.span()),
                _ => ("distance_m", 0..0),
            };
            self.err(
                &span,
                key,
                format!(
                    "{key}: the run covers {d:.1} m from s = {start:.2} m, so the leading wheelset ends at s = {lead_end:.1} m, \
                     beyond the end of track '{}' ({len:.1} m long); shorten the run or start earlier (start_m)",
                    track_file.display()
                ),
            );
            ok = false;
        }
        ok
    }
}

/// An `[initial]` key: value, name, unit, largest magnitude, degree of freedom, scale to SI.
type Check<'a> = (
    &'a Option<Spanned<f64>>,
    &'a str,
    &'a str,
    f64,
    DofKind,
    f64,
);

/// The span that starts first.
trait MinByStart {
    fn min_by_start(&self, other: &Range<usize>) -> Range<usize>;
}

impl MinByStart for Range<usize> {
    fn min_by_start(&self, other: &Range<usize>) -> Range<usize> {
        if self.start <= other.start {
            self.clone()
        } else {
            other.clone()
        }
    }
}

/// An integrator in the terms of a scene file's `[integrator]` table (docs/formats/scene.md),
/// e.g. `dopri5, rtol 1e-7, atol 1e-9, max_step_s unlimited`: what a run's log stores and
/// `railsim replay` lists.
pub fn integrator_text(m: &Method) -> String {
    let max_step = |h: f64| {
        if h.is_finite() {
            format!("max_step_s {}", short_number(h))
        } else {
            "max_step_s unlimited".to_owned()
        }
    };
    // the scene file has no initial step; a method built in code may fix one
    let initial = |h0: Option<f64>| {
        h0.map_or(String::new(), |h| {
            format!(", initial step {} s", short_number(h))
        })
    };
    match *m {
        Method::Rk4 { h } => format!("rk4, step_s {}", short_number(h)),
        Method::ExplicitFixed { tableau, h } => format!(
            "{} with a fixed step, step_s {}",
            tableau.name.to_ascii_lowercase(),
            short_number(h)
        ),
        Method::DormandPrince {
            rtol,
            atol,
            h0,
            h_max,
        } => format!(
            "dopri5, rtol {rtol:e}, atol {atol:e}, {}{}",
            max_step(h_max),
            initial(h0)
        ),
        Method::AdaptiveExplicit {
            tableau,
            rtol,
            atol,
            h0,
            h_max,
        } => format!(
            "{}, rtol {rtol:e}, atol {atol:e}, {}{}",
            tableau.name.to_ascii_lowercase(),
            max_step(h_max),
            initial(h0)
        ),
        Method::Radau5 {
            rtol,
            atol,
            h0,
            h_max,
            ..
        } => format!(
            "radau5, rtol {rtol:e}, atol {atol:e}, {}{}",
            max_step(h_max),
            initial(h0)
        ),
        Method::Radau5Fixed { h, rtol, atol } => format!(
            "radau5 with a fixed step, step_s {}, rtol {rtol:e}, atol {atol:e}",
            short_number(h)
        ),
    }
}

/// Track positions from `a` to `b` (both included) at most 0.25 m apart: where the start checks
/// look at the track under the vehicle.
fn span_points(a: f64, b: f64) -> impl Iterator<Item = f64> {
    let n = ((b - a) / 0.25).ceil().max(1.0) as usize;
    (0..=n).map(move |k| a + (b - a) * k as f64 / n as f64)
}

/// [`DEFAULT_FRICTION`] on both rails.
fn default_friction() -> [Friction; 2] {
    [0; 2].map(|_| Friction::Constant(DEFAULT_FRICTION))
}

/// The contact crate's friction of rail `k` (0 left, 1 right) of a checked [`FrictionSpec`]
/// (angles to radians).
pub fn friction_model(f: &FrictionSpec, k: usize) -> Friction {
    match f.rail(k) {
        FrictionSpec::Constant(x) => Friction::Constant(*x),
        FrictionSpec::ByContactAngle(t) => Friction::ByContactAngle {
            angle: t.contact_angle_deg.iter().map(|a| a.to_radians()).collect(),
            mu: t.coefficient.clone(),
        },
        // (refused by `FrictionSpec::problem`; one built in code resolves the same way)
        nested @ FrictionSpec::PerRail(_) => friction_model(nested, k),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_time_and_distance_are_inverse() {
        let p = SpeedProfile::from_points(vec![0.0, 100.0, 300.0], vec![10.0, 30.0, 30.0]).unwrap();
        assert_eq!(p.speed_at(50.0), 20.0);
        assert_eq!(p.speed_at(1000.0), 30.0);
        // v = 10 + 0.2 d on [0, 100]: t = ln(30/10)/0.2.
        assert!((p.time_at(100.0) - 3f64.ln() / 0.2).abs() < 1e-12);
        assert!((p.time_at(400.0) - (3f64.ln() / 0.2 + 10.0)).abs() < 1e-12);
        for d in [0.0, 1.0, 50.0, 99.9, 100.0, 250.0, 1000.0] {
            assert!((p.distance_at(p.time_at(d)) - d).abs() < 1e-9, "{d}");
        }
        let c = SpeedProfile::constant(55.0);
        assert_eq!(c.distance_at(2.0), 110.0);
        assert_eq!(c.time_at(110.0), 2.0);
        assert!(SpeedProfile::from_points(vec![1.0, 2.0], vec![1.0, 1.0]).is_none());
        assert!(SpeedProfile::from_points(vec![0.0, 2.0], vec![1.0, -1.0]).is_none());
    }

    #[test]
    fn normalize_removes_parent_components() {
        assert_eq!(
            normalize(Path::new("scenes/../vehicles/x.toml")),
            PathBuf::from("vehicles/x.toml")
        );
        assert_eq!(normalize(Path::new("../a/./b")), PathBuf::from("../a/b"));
        assert_eq!(normalize(Path::new("/r/s/../t")), PathBuf::from("/r/t"));
    }
}
