//! `railsim run [SCENE]`: simulate a scene with a progress line, an MCAP log and a summary.

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context as _, Result};
use clap::Args;

use railsim_ode::Method;
use railsim_sim::assess::{
    Assessment, CARBODY_BAND, MIN_F0_RECORD, SPERLING_BAND, STABILITY_WINDOW, SUM_Y_WINDOW,
    SectionReport, SectionZone, VerticalWeighting, default_assessment_rate,
};
use railsim_sim::{RunOptions, RunSummary, Scene, SimError, Simulation};

/// The built-in default scene, from the repository this binary was built in.
pub const DEFAULT_SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/default.toml");

#[derive(Args)]
pub struct RunArgs {
    /// Scene file (TOML, docs/formats/scene.md); default: the built-in scene
    /// (scenes/default.toml).
    pub scene: Option<PathBuf>,
    /// Write the log here instead of the scene's `[log]` path.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write no log.
    #[arg(long)]
    pub no_log: bool,
    /// Stop after this much simulated time, in seconds, instead of the scene's end.
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Measure and print the cost split (contact, suspension, integrator, logging).
    #[arg(long)]
    pub timing: bool,
    /// No progress line.
    #[arg(long, short)]
    pub quiet: bool,
    /// Write the per-section statistics (the scene's `[assessment] section_length_m`) to this
    /// CSV file: one row per quantity, axle, wheel or carbody point, zone and section.
    #[arg(long, value_name = "FILE")]
    pub sections_csv: Option<PathBuf>,
}

/// The texts a log stores so that it describes itself and can be re-run: the scene, vehicle
/// and track files, with their absolute paths (relative ones were relative to the directory the
/// run started in, so `replay --rerun` failed from any other), and under [`DATA_FILES`] a digest
/// and the absolute path of every data file the scene read (profiles, irregularities: they can
/// be large, so only their digests).
pub fn sources(scene_path: &Path, scene: &Scene) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    for (key, path) in [
        ("scene", scene_path),
        ("vehicle", scene.vehicle_file.as_path()),
        ("track", scene.track_file.as_path()),
    ] {
        if let Ok(text) = std::fs::read_to_string(path) {
            m.insert(key.to_owned(), text);
            m.insert(format!("{key}_path"), absolute(path));
        }
    }
    let mut lines = String::new();
    for path in scene.data_files() {
        if let Ok(bytes) = std::fs::read(path) {
            lines += &format!("{} {}\n", file_digest(&bytes), absolute(path));
        }
    }
    if !lines.is_empty() {
        m.insert(DATA_FILES.to_owned(), lines);
    }
    m
}

/// The key of [`sources`] under which the data files are listed, one per line:
/// `fnv1a64:<16 hex digits> <absolute path>`.
pub const DATA_FILES: &str = "data_files";

fn absolute(path: &Path) -> String {
    let absolute = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    absolute.display().to_string()
}

/// A file's FNV-1a 64-bit digest ([`railsim_sim::run::fnv1a`], the state digest's hash), as
/// written in [`DATA_FILES`]: enough to tell a changed file from its logged version, not meant
/// to resist a forger.
pub fn file_digest(bytes: &[u8]) -> String {
    let mut h = railsim_sim::run::FNV1A_OFFSET;
    railsim_sim::run::fnv1a(&mut h, bytes);
    format!("fnv1a64:{h:016x}")
}

pub fn run_scene(a: &RunArgs) -> Result<ExitCode> {
    let path = a
        .scene
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENE));
    if let Some(d) = a.duration_s
        && !(d.is_finite() && d > 0.0)
    {
        anyhow::bail!("--duration-s: expected a positive number of seconds, found {d}");
    }
    let scene = Scene::from_file(&path)?;
    if let Some(out) = &a.out {
        crate::check_log_out(out, &path, &scene)?;
    }
    if let Some(csv) = &a.sections_csv {
        crate::check_extension("--sections-csv", csv, &["csv"])?;
        if scene.assessment.sections.is_none() {
            anyhow::bail!(
                "--sections-csv: the scene {} sets no [assessment] section_length_m: expected the \
                 sections' length there (docs/formats/scene.md)",
                path.display()
            );
        }
    }
    if let Some(d) = a.duration_s
        && d > scene.duration() * (1.0 + 1e-12)
    {
        anyhow::bail!(
            "--duration-s {}: the scene ends after {} s (its duration_s, or its track and distance); expected at most that",
            railsim_profile::short_number(d),
            railsim_profile::short_number(scene.duration())
        );
    }
    let mut sim = Simulation::new(&scene)?;
    let opts = RunOptions {
        log_path: a.out.clone(),
        no_log: a.no_log,
        t_end: a.duration_s,
        timing: a.timing,
        sources: sources(&path, &scene),
    };
    let t_end = a
        .duration_s
        .unwrap_or(scene.duration())
        .min(scene.duration());
    eprintln!(
        "railsim run: {} ({} m/s, {:.2} s, contact model {}, {} states)",
        scene.name,
        scene.speed.speed_at(0.0),
        t_end,
        scene.contact.model.name(),
        sim.model().dim()
    );
    if let Some(note) = low_speed_note(&scene) {
        eprintln!("note: {note}");
    }
    if let Some(note) = aliasing_note(&scene) {
        eprintln!("note: {note}");
    }
    if let Some((iterations, residual)) = sim.quasi_static_start() {
        eprintln!(
            "initial state: quasi-static at s = {:.2} m ({iterations} Newton iterations, largest residual {residual:.2} of its limit)",
            scene.start
        );
    }
    let mut progress = throttled(a.quiet, |t, t_end, w| {
        let frac = (t / t_end).clamp(0.0, 1.0);
        let n = (frac * 30.0).round() as usize;
        eprint!(
            "\r[{}{}] t = {t:7.3} / {t_end:.3} s   real {w:7.1} s   {:.2}× real time ",
            "#".repeat(n),
            ".".repeat(30 - n),
            t / w.max(1e-9)
        );
    });
    let result = sim.run(&scene, &opts, &mut progress, &mut |_| {});
    if !a.quiet {
        eprintln!();
    }
    let summary = match result {
        Ok(summary) => summary,
        Err(mut e) => {
            // What the run recorded before it stopped: printed first, then the error.
            if let SimError::Stopped { t, summary, .. } = &mut e
                && let Some(s) = summary.take()
            {
                outln!(
                    "run STOPPED at t = {t:.6} s (error below); the summary and the assessment \
                     cover the samples up to the stop:"
                );
                print_summary(&s, a.timing)?;
                // (a failed write must not hide why the run stopped)
                if let Err(w) = write_sections_csv(a.sections_csv.as_deref(), &s) {
                    eprintln!("warning: --sections-csv: {w:#}");
                }
            }
            let note = match e {
                SimError::Stopped { .. } => stability_note(
                    &scene.integrator,
                    scene.track.rail_support().map(|r| r.mass),
                ),
                _ => None,
            };
            let err = anyhow::Error::from(e).context("railsim run");
            return Err(match note {
                Some(note) => anyhow::anyhow!("{}\nnote: {note}", crate::message(&err)),
                None => err,
            });
        }
    };
    print_summary(&summary, a.timing)?;
    write_sections_csv(a.sections_csv.as_deref(), &summary)?;
    Ok(ExitCode::SUCCESS)
}

/// `--sections-csv`: the per-section statistics of run `s`, a row per quantity, axle, wheel or
/// carbody point, zone and section, values in SI units (N, 1 for Y/Q, m/s² for the carbody's
/// accelerations).
fn write_sections_csv(path: Option<&Path>, s: &RunSummary) -> Result<()> {
    let (Some(path), Some(o)) = (path, s.assessment.sections) else {
        return Ok(());
    };
    let mut text =
        String::from("quantity,unit,wheelset,name,side,zone,section_start_m,section_end_m,value\n");
    let names = &s.wheelset_names;
    // `ws` the wheelset's number, `name` its name or a carbody point's
    let mut rows = |quantity: &str,
                    unit: &str,
                    (ws, name): (&str, &str),
                    side: &str,
                    r: &Option<SectionReport>| {
        for (zone, st) in r.iter().flat_map(|r| &r.zones) {
            let zone = zone.name();
            for v in &st.values {
                text += &format!(
                    "{quantity},{unit},{ws},{},{side},{zone},{},{},{}\n",
                    crate::curving::csv_field(name),
                    v.start,
                    v.start + o.length,
                    v.value
                );
            }
        }
    };
    let ws = |n: u32| {
        (
            n.to_string(),
            names.get(n as usize).map_or("", String::as_str),
        )
    };
    for ax in &s.assessment.axles {
        let (n, name) = ws(ax.wheelset);
        rows("sum_y_2m", "N", (&n, name), "", &ax.sum_y_2m_sections);
    }
    for w in &s.assessment.wheels {
        let ((n, name), side) = (ws(w.wheelset), w.side.name());
        rows("y_over_q_2m", "1", (&n, name), side, &w.y_over_q_sections);
        rows("q", "N", (&n, name), side, &w.q_sections);
    }
    for c in &s.assessment.comfort {
        let at = ("", c.name.as_str());
        for (k, direction) in ["lateral", "vertical"].into_iter().enumerate() {
            let max = format!("carbody_{direction}_max");
            rows(&max, "m/s2", at, "", &c.max_sections[k]);
            let rms = format!("carbody_{direction}_rms");
            rows(&rms, "m/s2", at, "", &c.rms_sections[k]);
        }
    }
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// A progress callback of a run, `(t, t_end)`: unless `quiet`, calls `show(t, t_end, wall)`
/// (wall-clock seconds since its creation) at most every half second and at the end, then
/// flushes standard error.
pub fn throttled(quiet: bool, mut show: impl FnMut(f64, f64, f64)) -> impl FnMut(f64, f64) {
    let wall = Instant::now();
    let mut last = 0.0f64;
    move |t, t_end| {
        let w = wall.elapsed().as_secs_f64();
        if !quiet && (w - last > 0.5 || t >= t_end) {
            last = w;
            show(t, t_end, w);
            let _ = std::io::stderr().flush();
        }
    }
}

/// \[s\] fixed explicit steps above this may exceed the stability limit that the wheel/rail
/// contact stiffness and the creep damping set (about 3-4 ms, docs/models/dynamics.md); the
/// shipped RK4 scene runs at 2 ms.
const EXPLICIT_STEP_NOTE: f64 = 2e-3;
/// \[N/m\] normal stiffness of a wheel/rail contact at a static wheel load near 55 kN
/// (Hertz: 1.5 N/δ with δ ≈ 55 µm), for the rail mode of an elastic rail support.
const CONTACT_STIFFNESS: f64 = 1.5e9;
/// RK4's stability limit on the imaginary axis, h ω ≤ 2√2.
const RK4_IMAGINARY_LIMIT: f64 = 2.828;
/// \[m\] absolute tolerances from this on are loose enough for the error control to let a
/// numerical instability grow (the default is 1e-6).
const LOOSE_ATOL: f64 = 1e-3;

/// \[m/s\] at and below this top speed an adaptive explicit integrator is noted as the slower
/// choice: the creep forces' damping grows as C/V and bounds its steps by stability. Measured on
/// the default scene's first second (docs/performance.md, "Choosing the integrator"): Radau5 at
/// rtol 1e-5, atol 1e-7 against DOPRI5 at 1e-4 / 1e-7 took 1/140 of the time at 1 km/h, 1/45 at
/// 5, 1/6.8 at 20 and 1/1.4 at 50 km/h; at 198 km/h on irregular track DOPRI5 is about 5 times
/// the faster. The note carries the caveat found on the R = 150 m curve at 40 km/h: there
/// Radau5 at those tolerances damped out a friction-induced oscillation that both
/// tight-tolerance solutions show. Until stop 31 it excepted STRIPES on an elastic rail support,
/// where Radau5 was the slower; since STRIPES integrates the junctions of the profiles' arcs at
/// sub-points, Radau5 runs the elastic R = 150 m scene in 4.4 s against DOPRI5's 55.6 s
/// (docs/performance.md).
const LOW_SPEED: f64 = 50.0 / 3.6;

/// A note before a run with an adaptive explicit integrator whose top speed is at most
/// [`LOW_SPEED`]; `None` otherwise.
fn low_speed_note(scene: &Scene) -> Option<String> {
    let top = scene.speed.speeds().iter().copied().fold(0.0, f64::max);
    let explicit = matches!(
        scene.integrator,
        Method::DormandPrince { .. } | Method::AdaptiveExplicit { .. }
    );
    (explicit && top <= LOW_SPEED + 1e-9).then(|| {
        format!(
            "at {:.0} km/h the creep forces' damping (about C/V) bounds an explicit method's \
             steps by stability: radau5 at rtol 1e-5, atol 1e-7 was measured 1.4 (50 km/h) to \
             140 (1 km/h) times faster, but it can damp out an oscillation it does not resolve \
             (it did on the R = 150 m curve at 40 km/h): check a case that may oscillate at \
             tight tolerances (docs/performance.md, \"Choosing the integrator\")",
            top * 3.6
        )
    })
}

/// A note before a run whose assessment samples come at less than the contact model's
/// [`default_assessment_rate`], which only a scene's own `[assessment] rate_hz` can make
/// happen: they are taken without an anti-aliasing filter (found in stop 32: assessed at the
/// default scene's 200 Hz log rate, the Q percentiles are up to 8.2 kN higher than at 1 kHz).
fn aliasing_note(scene: &Scene) -> Option<String> {
    let rate = scene.assessment_rate();
    let default = default_assessment_rate(scene.contact.model);
    (rate < default).then(|| {
        format!(
            "the EN 14363 statistics below come from samples at {rate} Hz ([assessment] rate_hz) \
             without an anti-aliasing filter: wheel forces above {} Hz (the wheelsets on the \
             contact stiffness, 120-220 Hz, and flange impacts) fold into the 20 Hz band and can \
             overstate Q by several kN; without the key the assessment samples at the log rate's \
             multiple at or above {default} Hz for contact model {} \
             (docs/models/dynamics.md, \"Aliasing\")",
            rate / 2.0,
            scene.contact.model.name()
        )
    })
}

/// For a run that stopped (derailment, instability, a contact limit): a note when the
/// integrator's settings can produce the same stop numerically, with how to tell. `rail_mass`
/// \[kg\] is the rail mass of an elastic rail support: on the contact stiffness it has a mode
/// that lowers the stability limit of fixed explicit steps to about 2√2 √(m / k).
fn stability_note(method: &Method, rail_mass: Option<f64>) -> Option<String> {
    let (limit, what) = match rail_mass {
        Some(m) => (
            EXPLICIT_STEP_NOTE.min(RK4_IMAGINARY_LIMIT * (m / CONTACT_STIFFNESS).sqrt()),
            format!("the wheel/rail contact and the elastic rail support's {m} kg rail masses"),
        ),
        None => (EXPLICIT_STEP_NOTE, "the wheel/rail contact".to_owned()),
    };
    match *method {
        Method::Rk4 { h } | Method::ExplicitFixed { h, .. } if h > limit => Some(format!(
            "the run used a fixed explicit step of {} ms; above about {:.2} ms such a step can \
             exceed the stability limit set by {what}, and a numerical instability stops a run \
             the same way: rerun with a smaller step_s to tell",
            h * 1e3,
            limit * 1e3
        )),
        Method::DormandPrince { atol, .. } | Method::AdaptiveExplicit { atol, .. }
            if atol >= LOOSE_ATOL =>
        {
            Some(format!(
                "the run used atol = {atol} m; tolerances this loose can let a numerical \
                 instability grow unnoticed, and it stops a run the same way: rerun with \
                 tighter tolerances to tell"
            ))
        }
        _ => None,
    }
}

/// The assessment lines of the summary: EN 14363's track-shift force per axle, and the
/// carbody's ride quantities per point.
/// Per wheel: (Y/Q)2m, Q, and the quasi-static forces in the curves.
/// "wheelset N (name)": a wheelset by its number from the front (the logs' `/wheelsets/N`)
/// and its name in the vehicle file.
pub(crate) fn wheelset(names: &[String], n: impl Into<u64>) -> String {
    let n = n.into();
    match names.get(n as usize) {
        Some(name) => format!("wheelset {n} ({name})"),
        None => format!("wheelset {n}"),
    }
}

fn print_wheels(a: &Assessment, names: &[String]) -> Result<()> {
    if a.wheels.is_empty() {
        return Ok(());
    }
    let l = &a.limits;
    let q_limit = match l.q {
        Some(q) => format!("{:.1} kN", q * 1e-3),
        None => format!(
            "90 kN + Q0 capped for the top speed {:.0} km/h",
            a.top_speed * 3.6
        ),
    };
    outln!(
        "running safety and vertical force per wheel (EN 14363; Y, Q low-passed 20 Hz{}; \
         99.85 % percentiles of (Y/Q)2m and of Q; limits (Y/Q)2m {} ({} in curves under \
         {:.0} m), Q {q_limit}):",
        if a.lowpass {
            ""
        } else {
            " where the log rate allows: not applied"
        },
        l.y_over_q,
        l.y_over_q_small_radius,
        l.small_radius
    );
    let flag = |v: f64, lim: f64| if v > lim { " EXCEEDED" } else { "" };
    for w in &a.wheels {
        let mut parts: Vec<String> = w
            .y_over_q
            .iter()
            .map(|z| {
                format!(
                    "(Y/Q)2m{} {:.3} (max {:.3} at {:.1} m, {} windows), limit {}{}",
                    if z.small_radius {
                        " in small radii"
                    } else {
                        ""
                    },
                    z.percentile,
                    z.largest.value,
                    z.largest.at,
                    z.windows,
                    z.limit,
                    flag(z.percentile, z.limit)
                )
            })
            .collect();
        if parts.is_empty() {
            parts.push(format!(
                "no (Y/Q)2m (the run covered less than {SUM_Y_WINDOW} m)"
            ));
        }
        if let (Some(p), Some(m)) = (w.q_percentile, w.q_max) {
            parts.push(format!(
                "Q {:.1} kN (max {:.1}), limit {:.1} kN{}",
                p * 1e-3,
                m * 1e-3,
                w.q_limit * 1e-3,
                flag(p, w.q_limit)
            ));
        }
        if let Some(m) = w.q_min {
            parts.push(format!(
                "Q min {:.1} kN at {:.1} m (ΔQ/Q0 {:.2})",
                m.value * 1e-3,
                m.at,
                1.0 - m.value / w.static_load
            ));
        }
        if let (lifted, Some(from)) = w.lifted {
            parts.push(format!(
                "WHEEL LIFTED over {lifted:.2} m, first at {from:.1} m"
            ));
        }
        outln!(
            "  {} {}: {}",
            wheelset(names, w.wheelset),
            w.side.name(),
            parts.join("; ")
        );
    }
    let curves: Vec<_> = a
        .wheels
        .iter()
        .flat_map(|w| w.quasi_static.iter().map(move |q| (w, q)))
        .collect();
    if !curves.is_empty() {
        outln!(
            "quasi-static wheel forces in the circular curves (medians; limits Y_qst {:.0} kN, \
             Q_qst {:.0} kN on the outer wheel):",
            l.y_qst * 1e-3,
            l.q_qst * 1e-3
        );
        for (w, q) in curves {
            let verdict = if q.outer {
                format!(
                    "{}{}",
                    flag(q.y_qst, l.y_qst).replace("EXCEEDED", "Y_qst EXCEEDED"),
                    flag(q.q_qst, l.q_qst).replace("EXCEEDED", "Q_qst EXCEEDED")
                )
            } else {
                String::new()
            };
            outln!(
                "  curve {} (R {:.0} m): {} {}{}: Y_qst {:.2} kN, Q_qst {:.2} kN \
                 ({} samples){verdict}",
                q.curve,
                q.radius,
                wheelset(names, w.wheelset),
                w.side.name(),
                if q.outer { " (outer)" } else { "" },
                q.y_qst * 1e-3,
                q.q_qst * 1e-3,
                q.samples
            );
        }
    }
    Ok(())
}

/// The per-section statistics (`[assessment] section_length_m`), per axle, wheel and carbody
/// point and per zone of the track: the number of sections, their mean, standard deviation, largest and
/// estimate, against the quantity's limit.
fn print_sections(a: &Assessment, names: &[String]) -> Result<()> {
    let Some(o) = a.sections else {
        return Ok(());
    };
    let l = &a.limits;
    outln!(
        "per track section of {} m (the statistic above in each section a wheelset or carbody \
         point ran through whole, by zone: off curves (tangent track and transitions), in curves, in curves under \
         {:.0} m; a section across zones is left out; over a zone's sections: their number, \
         mean, standard deviation s, largest{}):",
        o.length,
        l.small_radius,
        o.k.map_or_else(String::new, |k| format!(
            ", estimate mean + k s with k = {k}"
        ))
    );
    let sections = |n: usize| format!("{n} section{}", if n == 1 { "" } else { "s" });
    // one quantity's zones; `limit` by zone, values scaled to the unit
    let line = |what: &str,
                r: &Option<SectionReport>,
                (scale, unit): (f64, &str),
                limit: &dyn Fn(SectionZone) -> Option<f64>| {
        let Some(r) = r else {
            return format!("{what} no whole section");
        };
        let v = |x: f64| format!("{:.3}{unit}", x * scale);
        let mut parts: Vec<String> = r
            .zones
            .iter()
            .map(|(z, st)| {
                let zone = match z {
                    SectionZone::OffCurves => "off curves",
                    SectionZone::Curves => "in curves",
                    SectionZone::SmallRadius => "in small radii",
                };
                let mut out = format!(
                    "{what} {zone} {}, mean {}, s {}, largest {} ({:.0}-{:.0} m)",
                    sections(st.values.len()),
                    v(st.mean),
                    st.std_dev.map_or_else(|| "-".to_owned(), v),
                    v(st.largest.value),
                    st.largest.start,
                    st.largest.start + o.length
                );
                if let Some(e) = st.estimate {
                    out += &format!(", estimate {}", v(e));
                }
                if let Some(lim) = limit(*z) {
                    let top = st.estimate.unwrap_or(st.largest.value);
                    let verdict = if top > lim { " EXCEEDED" } else { "" };
                    out += &format!(", limit {}{verdict}", v(lim));
                }
                out
            })
            .collect();
        if r.mixed > 0 {
            parts.push(format!(
                "{what} {} across zones left out",
                sections(r.mixed)
            ));
        }
        if parts.is_empty() {
            parts.push(format!("{what} no whole section"));
        }
        parts.join("; ")
    };
    for ax in &a.axles {
        let sections = line("(ΣY)2m", &ax.sum_y_2m_sections, (1e-3, " kN"), &|_| {
            Some(ax.sum_y_limit)
        });
        outln!("  {}: {sections}", wheelset(names, ax.wheelset));
    }
    let yq_limit = |z| {
        Some(if z == SectionZone::SmallRadius {
            l.y_over_q_small_radius
        } else {
            l.y_over_q
        })
    };
    for w in &a.wheels {
        let yq = line("(Y/Q)2m", &w.y_over_q_sections, (1.0, ""), &yq_limit);
        let q = line("Q", &w.q_sections, (1e-3, " kN"), &|_| Some(w.q_limit));
        outln!(
            "  {} {}: {yq}; {q}",
            wheelset(names, w.wheelset),
            w.side.name()
        );
    }
    // the carbody's band-passed accelerations (no limit is built in for them)
    for c in &a.comfort {
        let unit = (1.0, " m/s²");
        let mut parts = Vec::new();
        for (k, axis) in ["ÿ*", "z̈*"].into_iter().enumerate() {
            if c.band_passed[k].is_none() {
                parts.push(format!("{axis} - (log rate under 20 Hz)"));
                continue;
            }
            parts.push(line(
                &format!("{axis} max"),
                &c.max_sections[k],
                unit,
                &|_| None,
            ));
            parts.push(line(
                &format!("{axis} r.m.s."),
                &c.rms_sections[k],
                unit,
                &|_| None,
            ));
        }
        outln!("  {}: {}", c.name, parts.join("; "));
    }
    Ok(())
}

/// Per bogie frame: the simplified stability criterion.
fn print_bogies(a: &Assessment) -> Result<()> {
    if a.bogies.is_empty() {
        return Ok(());
    }
    outln!(
        "bogie frames, simplified stability method (lateral acceleration above each wheelset, \
         band-passed around f0; limits 12 - m_b/5 m/s² peak, half of it r.m.s. over \
         {STABILITY_WINDOW} m):"
    );
    for b in &a.bogies {
        for p in &b.points {
            let peak = p.peak.map_or_else(
                || "no peak (no band)".to_owned(),
                |e| {
                    format!(
                        "peak {:.2} m/s² at {:.0} m{}",
                        e.value.abs(),
                        e.at,
                        if e.value.abs() > b.peak_limit {
                            " EXCEEDED"
                        } else {
                            ""
                        }
                    )
                },
            );
            let rms = p.rms.map_or_else(
                || "no r.m.s.".to_owned(),
                |e| {
                    format!(
                        "r.m.s. {:.2} m/s² at {:.0} m{}",
                        e.value,
                        e.at,
                        if e.value > b.rms_limit() {
                            " EXCEEDED"
                        } else {
                            ""
                        }
                    )
                },
            );
            outln!(
                "  {}: {peak}; {rms}; limits {:.2} / {:.2} m/s² (m_b {:.2} t)",
                p.name,
                b.peak_limit,
                b.rms_limit(),
                b.mass * 1e-3
            );
        }
    }
    Ok(())
}

fn print_assessment(a: &Assessment, names: &[String]) -> Result<()> {
    let band = match (a.band, a.instability_frequency) {
        (Some((lo, hi)), Some((f0, found))) => format!(
            "band-passed {lo:.2}-{hi:.2} Hz around f0 = {f0:.2} Hz ({})",
            if found {
                "the dominant frequency of ΣY"
            } else {
                "given"
            }
        ),
        (None, Some((f0, _))) => {
            format!("f0 = {f0:.2} Hz, whose band the log rate cannot carry: no r.m.s. criterion")
        }
        _ if a.too_short_for_f0 => format!(
            "no instability frequency (a record under {MIN_F0_RECORD} s has none): no r.m.s. \
             criterion"
        ),
        _ => "no instability frequency found: no r.m.s. criterion".to_owned(),
    };
    outln!(
        "track-shift force ΣY (EN 14363; limit α(10 kN + 2Q0/3), α = {}{}; stability: sliding \
         r.m.s. over {STABILITY_WINDOW} m of ΣY {band}, limit half of it):",
        a.alpha,
        if a.lowpass {
            ""
        } else {
            "; the log rate is too low for the 20 Hz low-pass, not applied"
        }
    );
    let verdict = |v: f64, lim: f64| if v.abs() > lim { " EXCEEDED" } else { "" };
    for ax in &a.axles {
        let lim = ax.sum_y_limit;
        let mean = match (ax.sum_y_2m, ax.sum_y_2m_percentile) {
            (Some(m), Some(p)) => format!(
                "(ΣY)2m max {:.2} kN at {:.1} m, percentile statistic {:.2} kN, limit {:.2} kN{}",
                m.value * 1e-3,
                m.at,
                p * 1e-3,
                lim * 1e-3,
                verdict(p, lim)
            ),
            _ => format!("no (ΣY)2m (the run covered less than {SUM_Y_WINDOW} m)"),
        };
        let rms = match ax.sum_y_rms {
            Some(r) => format!(
                "r.m.s. max {:.2} kN at {:.0} m, limit {:.2} kN{}",
                r.value * 1e-3,
                r.at,
                ax.rms_limit() * 1e-3,
                verdict(r.value, ax.rms_limit())
            ),
            None if a.band.is_some() => {
                format!("no r.m.s. (the run covered less than {STABILITY_WINDOW} m)")
            }
            None => "no r.m.s.".to_owned(),
        };
        outln!("  {}: {mean}; {rms}", wheelset(names, ax.wheelset));
    }
    print_wheels(a, names)?;
    print_sections(a, names)?;
    print_bogies(a)?;
    if !a.comfort.is_empty() {
        outln!(
            "carbody accelerations, lateral / vertical: Sperling's ride index Wz ({}-{} Hz); \
             max (0.15 % / 99.85 % percentiles) and r.m.s. band-passed {}-{} Hz (EN 14363):",
            SPERLING_BAND.0,
            SPERLING_BAND.1,
            CARBODY_BAND.0,
            CARBODY_BAND.1
        );
        let wz = |w: Option<f64>| {
            w.map_or_else(|| "- (run under 2 s)".to_owned(), |w| format!("{w:.2}"))
        };
        let acc = |b: Option<(f64, f64)>| {
            b.map_or_else(
                || "- (log rate under 20 Hz)".to_owned(),
                |(m, r)| format!("{m:.2} and {r:.3} m/s²"),
            )
        };
        for c in &a.comfort {
            let n_mv = c.n_mv.map_or_else(
                || "N_MV - (run under 5 s)".to_owned(),
                |(n, w)| {
                    let w_b = match a.vertical_weighting {
                        VerticalWeighting::En12299 => "",
                        VerticalWeighting::Iso2631_4 => " (W_b of ISO 2631-4)",
                    };
                    format!("EN 12299 N_MV {n:.2} over {w} windows of 5 s{w_b}")
                },
            );
            outln!(
                "  {}: Wz {} / {}; {} / {}; {n_mv}",
                c.name,
                wz(c.wz[0]),
                wz(c.wz[1]),
                acc(c.band_passed[0]),
                acc(c.band_passed[1])
            );
        }
    }
    Ok(())
}

/// The energy the dissipative force elements dissipated over the run, largest first.
fn print_element_energy(s: &RunSummary) -> Result<()> {
    let mut dissipative: Vec<_> = s.elements.iter().filter(|e| e.dissipates).collect();
    if dissipative.is_empty() {
        return Ok(());
    }
    dissipative.sort_by(|a, b| b.dissipated.total_cmp(&a.dissipated));
    outln!("suspension dissipation (dampers and friction, over the samples; mean and peak power):");
    for e in dissipative {
        outln!(
            "  {} ({}): {:.3} kJ, mean {:.1} W, peak {:.1} W",
            e.name,
            e.kind,
            e.dissipated * 1e-3,
            e.mean_dissipation,
            e.peak_dissipation
        );
    }
    Ok(())
}

fn print_summary(s: &RunSummary, timing: bool) -> Result<()> {
    outln!(
        "simulated {:.3} s in {:.2} s: real-time factor {:.3}",
        s.t_end,
        s.wall,
        s.real_time_factor()
    );
    let names = &s.wheelset_names;
    for (i, y) in s.max_lateral.iter().enumerate() {
        outln!(
            "{}: max |lateral displacement| {:.2} mm",
            wheelset(names, i as u64),
            y * 1e3
        );
    }
    let side = |x: railsim_contact::Side| x.name();
    let at = |m: Option<(f64, u32, railsim_contact::Side)>, what: &str, none: &str| match m {
        Some((v, n, sd)) => format!("{v:.3} {what} ({}, {} wheel)", wheelset(names, n), side(sd)),
        None => format!("none {what} ({none})"),
    };
    outln!(
        "max Y/Q {}; max Q {:.1} kN ({}, {} wheel)",
        at(s.max_y_over_q, "at a sample", "no samples"),
        s.max_q.0 * 1e-3,
        wheelset(names, s.max_q.1),
        side(s.max_q.2)
    );
    outln!(
        "EN 14363 assessment, maxima at a sample and energies from the run's samples at {} Hz",
        s.assessment_rate_hz
    );
    print_assessment(&s.assessment, names)?;
    if let Some([lat, vert]) = s.max_rail {
        outln!(
            "elastic rail support: max rail displacement {:.3} mm lateral ({}, {} wheel), \
             {:.3} mm vertical ({}, {} wheel)",
            lat.0 * 1e3,
            wheelset(names, lat.1),
            side(lat.2),
            vert.0 * 1e3,
            wheelset(names, vert.1),
            side(vert.2)
        );
    }
    print_element_energy(s)?;
    let st = &s.stats;
    outln!(
        "integrator: {} steps ({} limited by stability), {} rejected, {} right-hand sides, {} \
         Jacobians, {} LU",
        st.steps,
        st.stability_limited,
        st.rejected,
        st.rhs_evals,
        st.jacobians,
        st.lu_factorizations
    );
    if st.newton_iterations > 0 {
        outln!(
            "integrator: {} simplified-Newton iterations, {} step attempts abandoned because \
             Newton diverged or converged too slowly",
            st.newton_iterations,
            st.newton_failures
        );
    }
    if let Some(each) = st.jacobian_rhs_evals.checked_div(st.jacobians) {
        outln!(
            "integrator: the Jacobians took {} right-hand sides ({each} each, by column groups \
             of the model's coupling pattern)",
            st.jacobian_rhs_evals,
        );
    }
    if st.trial_failures > 0 {
        outln!(
            "integrator: {} step attempts rejected because the model could not be evaluated at a \
             trial state (e.g. a contact beyond its limits), retried shorter",
            st.trial_failures
        );
    }
    if let Some(t) = st.stiff_from {
        outln!(
            "integrator: the steps were limited by stability, not accuracy ({} of {} steps; \
             stiff from t = {t:.3} s): a weakly damped stiff mode can keep an oscillation of the \
             order of atol, which shows in the wheel loads; a smaller atol shrinks it in \
             proportion (measured on the default scene: atol 1e-7 against 1e-6, the wheel loads \
             0.2 kN r.m.s. from a tight-tolerance reference instead of 2.0 kN; the EN 14363 \
             statistics from 1 kHz samples alike at both), or radau5, which may also damp out a \
             real oscillation it does not resolve (docs/performance.md, \"Choosing the \
             integrator\")",
            st.stability_limited,
            st.steps
        );
    }
    let (warm, cold) = s.contact_searches;
    if warm + cold > 0 {
        outln!(
            "contact searches: {warm} warm-started, {cold} cold ({:.1} % warm)",
            100.0 * warm as f64 / (warm + cold) as f64
        );
    }
    outln!("samples {}; state digest {:016x}", s.samples, s.digest);
    if timing {
        let c = &s.cost;
        let other = (s.wall - c.rhs - s.logging).max(0.0);
        outln!(
            "cost: contact {:.2} s ({:.0} %), suspension {:.2} s ({:.0} %), rest of rhs {:.2} s, integrator and loop {:.2} s, logging {:.2} s",
            c.contact,
            100.0 * c.contact / s.wall,
            c.suspension,
            100.0 * c.suspension / s.wall,
            c.rhs - c.contact - c.suspension,
            other,
            s.logging
        );
    }
    if let Some(log) = &s.log {
        outln!(
            "log: {} ({} messages, {:.1} MB)",
            log.path.display(),
            log.messages,
            log.bytes as f64 / 1e6
        );
    }
    Ok(())
}
