//! Steady-state curving: a vehicle run at constant speed from straight track over a transition
//! into a circular curve of a given radius and cant, and the means of its running quantities
//! once it runs steadily in the curve: per wheelset the lateral displacement and the angle of
//! attack, per wheel Y, Q, Y/Q and the wear number Tγ, per axle the track-shift force, and the
//! carbody's lateral reading. This is the curving table of vehicle dynamics (e.g. Iwnicki (ed.),
//! *Handbook of Railway Vehicle Dynamics*, ch. on curving; EN 14363's quasi-static quantities
//! Y_qst, Q_qst are such means), computed by time integration of the full model rather than by a
//! quasi-static solver: the run itself shows whether the vehicle settles (`lateral_swing`).
//!
//! The track of a case is the scene's track file with its alignment replaced and its
//! irregularities removed (rail profiles, gauge, inclination, cant base and rail support kept):
//! a tangent that holds the whole vehicle at the start, a clothoid along which curvature and
//! cant grow linearly, and the curve. The rearmost wheelset starts at s = 0; the quantities are
//! averaged over `average` metres once the rearmost wheelset has run `settle` metres in the
//! curve.

use std::path::Path;

use railsim_track::{HARD_MIN_RADIUS_M, TrackModel, TrackSpec};

use crate::error::SimError;
use crate::run::{RunOptions, RunSummary, Sample, Simulation};
use crate::scene::{RunLength, Scene, SpeedProfile, extent, required_curve_radius};

/// \[m\] straight track ahead of the leading wheelset at the start.
const LEAD_MARGIN: f64 = 5.0;
/// \[m\] track beyond the leading wheelset at the end.
const END_MARGIN: f64 = 10.0;

/// One curve: radius, cant, side and the speed through it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveCase {
    /// \[m\] radius.
    pub radius: f64,
    /// \[m\] cant (outer rail above the inner one), ≥ 0.
    pub cant: f64,
    /// Whether the curve turns to the left (its centre on the left, seen in the direction of
    /// travel).
    pub left: bool,
    /// \[m/s\] constant speed.
    pub speed: f64,
}

/// Lengths of a curving run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvingRun {
    /// \[m\] length of the transition (clothoid, cant ramp).
    pub transition: f64,
    /// \[m\] distance the rearmost wheelset runs in the curve before the averaging starts.
    pub settle: f64,
    /// \[m\] distance over which the means are taken.
    pub average: f64,
}

impl Default for CurvingRun {
    fn default() -> Self {
        CurvingRun {
            transition: 80.0,
            settle: 100.0,
            average: 100.0,
        }
    }
}

/// Means of one wheel over the averaging stretch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelMeans {
    /// \[N\] lateral force on the rail, toward its field side.
    pub y: f64,
    /// \[N\] vertical force on the rail, downward.
    pub q: f64,
    /// \[-\] the mean of Y/Q.
    pub y_over_q: f64,
    /// \[N\] wear number Tγ, summed over the wheel's patches.
    pub wear: f64,
}

/// Means of one wheelset over the averaging stretch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetMeans {
    /// \[m\] lateral displacement relative to the track centre line, positive to the left.
    pub lateral: f64,
    /// \[rad\] angle of attack (yaw relative to the track), positive nose-left.
    pub angle_of_attack: f64,
    /// Left and right wheel.
    pub wheels: [WheelMeans; 2],
    /// \[N\] track-shift force ΣY, positive toward +y.
    pub sum_y: f64,
    /// \[m\] largest minus smallest lateral displacement during the averaging (0 for a vehicle
    /// that runs steadily).
    pub lateral_swing: f64,
}

/// The result of one curving case.
#[derive(Debug, Clone)]
pub struct SteadyCurving {
    /// The case.
    pub case: CurveCase,
    /// \[m/s²\] uncompensated lateral acceleration in the track plane,
    /// `v² cos φ / R − g sin |φ|` (toward the outside when positive).
    pub uncompensated: f64,
    /// \[m\] the cant deficiency it corresponds to: `a · cant base / g`.
    pub cant_deficiency: f64,
    /// Per wheelset, numbered from the front.
    pub wheelsets: Vec<WheelsetMeans>,
    /// \[m/s²\] mean lateral reading of an accelerometer at the carbody's centre (carbody axes,
    /// positive to the left); `None` for a vehicle without rigid bodies.
    pub carbody_lateral: Option<f64>,
    /// Samples averaged.
    pub samples: usize,
    /// The run's summary.
    pub summary: RunSummary,
}

/// The scene of a curving case: `scene` with the case's track (the scene's track file with its
/// alignment replaced and its irregularities removed), constant speed, the rearmost wheelset
/// starting at s = 0, no disturbance. Returns the scene and the track position where the curve
/// begins.
pub fn curving_scene(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
) -> Result<(Scene, f64), SimError> {
    let bad = |message: String| SimError::Study {
        message: format!("curving study of scene '{}': {message}", scene.name),
    };
    let required = required_curve_radius(&scene.vehicle).max(HARD_MIN_RADIUS_M);
    if !(case.radius.is_finite() && case.radius >= required) {
        return Err(bad(format!(
            "the radius must be at least {:.0} m (the track's lower limit, and what the \
             vehicle's rigid wheelbase needs), found {} m",
            required, case.radius
        )));
    }
    if !(case.cant >= 0.0 && case.cant <= 0.2) {
        return Err(bad(format!(
            "the cant must lie in [0, 200] mm, found {} mm",
            case.cant * 1e3
        )));
    }
    if !(case.speed > 0.0 && case.speed.is_finite()) {
        return Err(bad(format!(
            "the speed must be positive, found {} km/h",
            case.speed * 3.6
        )));
    }
    if !(run.transition > 0.0 && run.settle >= 0.0 && run.average > 0.0) {
        return Err(bad(format!(
            "the transition ({} m) and the averaging length ({} m) must be positive and the \
             settling distance ({} m) not negative",
            run.transition, run.average, run.settle
        )));
    }
    let (_, x_max, x_min) = extent(&scene.vehicle);
    let length = x_max - x_min;
    let lead_in = length + LEAD_MARGIN;
    let curve_start = lead_in + run.transition;
    let curve_len = run.settle + run.average + length + END_MARGIN;
    let track =
        case_track(&scene.track_file, case, lead_in, run.transition, curve_len).map_err(bad)?;
    let mut base = scene.clone();
    base.track = track;
    base.start = -x_min;
    let study = base.study(
        SpeedProfile::constant(case.speed),
        RunLength::Distance(curve_start + run.settle + run.average),
        0.0,
    )?;
    Ok((study, curve_start))
}

/// The track of a case, from the scene's track file.
fn case_track(
    file: &Path,
    case: &CurveCase,
    lead_in: f64,
    transition: f64,
    curve_len: f64,
) -> Result<TrackModel, String> {
    let side = if case.left { "left" } else { "right" };
    let curve = Some((case.radius, case.cant, side));
    smooth_track(
        file,
        &format!(
            "curving case R = {} m, cant {} mm",
            case.radius,
            case.cant * 1e3
        ),
        &[
            ("tangent", lead_in, None),
            ("clothoid", transition, None),
            ("curve", curve_len, curve),
        ],
    )
}

/// One segment of [`smooth_track`]: type, length \[m\], and for a curve its radius \[m\],
/// cant \[m\] and direction (`"left"` or `"right"`).
pub(crate) type Segment<'a> = (&'a str, f64, Option<(f64, f64, &'a str)>);

/// The track file `file` with its alignment replaced by `segments` and its irregularities
/// removed (rail profiles, gauge, inclination, cant base and rail support kept), named `what`
/// (the file's name is appended).
pub(crate) fn smooth_track(
    file: &Path,
    what: &str,
    segments: &[Segment],
) -> Result<TrackModel, String> {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file).map_err(|e| format!("cannot read {name}: {e}"))?;
    let mut table: toml::Table = text
        .parse()
        .map_err(|e| format!("{name}: not a TOML table: {e}"))?;
    table.remove("irregularities");
    table.insert(
        "name".into(),
        toml::Value::String(format!("{what} ({name})")),
    );
    let segment = |&(kind, length, curve): &Segment| {
        let mut t = toml::Table::new();
        t.insert("type".into(), toml::Value::String(kind.into()));
        t.insert("length_m".into(), toml::Value::Float(length));
        if let Some((radius, cant, side)) = curve {
            t.insert("radius_m".into(), toml::Value::Float(radius));
            t.insert("cant_mm".into(), toml::Value::Float(cant * 1e3));
            t.insert("direction".into(), toml::Value::String(side.into()));
        }
        toml::Value::Table(t)
    };
    table.insert(
        "segment".into(),
        toml::Value::Array(segments.iter().map(segment).collect()),
    );
    let text = toml::to_string(&table).map_err(|e| format!("{name}: {e}"))?;
    let spec = TrackSpec::from_toml_str(&text, &name).map_err(|e| e.to_string())?;
    TrackModel::compile(&spec, &name).map_err(|e| e.to_string())
}

/// Run one curving case of `scene` with `opts` and take the means (module docs).
pub fn steady_curving(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    opts: &RunOptions,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<SteadyCurving, SimError> {
    let (study, curve_start) = curving_scene(scene, case, run)?;
    let from = curve_start + run.settle;
    let mut sums: Vec<WheelsetMeans> = Vec::new();
    let mut ranges: Vec<(f64, f64)> = Vec::new();
    let mut carbody = 0.0;
    let mut n = 0usize;
    let mut sim = Simulation::new(&study)?;
    let summary = sim.run(&study, opts, progress, &mut |s: &Sample| {
        // the rearmost wheelset's distance run (it starts at s = 0) at constant speed
        if s.t * case.speed < from - 1e-9 {
            return;
        }
        if sums.is_empty() {
            sums = vec![WheelsetMeans::default(); s.wheelsets.len()];
            ranges = vec![(f64::INFINITY, f64::NEG_INFINITY); s.wheelsets.len()];
        }
        for ((m, w), (r, y)) in sums
            .iter_mut()
            .zip(&s.wheelsets)
            .zip(ranges.iter_mut().zip(&s.lateral))
        {
            m.lateral += y;
            *r = (r.0.min(*y), r.1.max(*y));
            m.angle_of_attack += w.angle_of_attack_rad;
            m.sum_y += w.y_left_n - w.y_right_n;
            let per_wheel = [
                (
                    w.y_left_n,
                    w.q_left_n,
                    w.y_over_q_left,
                    w.wear_number_left_n,
                ),
                (
                    w.y_right_n,
                    w.q_right_n,
                    w.y_over_q_right,
                    w.wear_number_right_n,
                ),
            ];
            for (wm, (y, q, yq, wear)) in m.wheels.iter_mut().zip(per_wheel) {
                wm.y += y;
                wm.q += q;
                wm.y_over_q += yq;
                wm.wear += wear;
            }
        }
        if let Some(c) = s.carbody.first() {
            carbody += c[1];
        }
        n += 1;
    })?;
    if n == 0 {
        return Err(SimError::Study {
            message: format!(
                "curving study of scene '{}': no sample in the averaging stretch (log rate {} Hz)",
                scene.name, study.log.rate_hz
            ),
        });
    }
    let k = 1.0 / n as f64;
    for (m, r) in sums.iter_mut().zip(&ranges) {
        m.lateral *= k;
        m.angle_of_attack *= k;
        m.sum_y *= k;
        m.lateral_swing = r.1 - r.0;
        for w in &mut m.wheels {
            w.y *= k;
            w.q *= k;
            w.y_over_q *= k;
            w.wear *= k;
        }
    }
    let frame = study.track.frame_at(curve_start + 0.5 * run.settle);
    let g = study.vehicle.gravity();
    let uncompensated = case.speed * case.speed * frame.curvature.abs() * frame.roll.cos()
        - g * frame.roll.abs().sin();
    Ok(SteadyCurving {
        case: *case,
        uncompensated,
        cant_deficiency: uncompensated * study.track.cant_base() / g,
        wheelsets: sums,
        carbody_lateral: (!summary.assessment.comfort.is_empty()).then_some(carbody * k),
        samples: n,
        summary,
    })
}
