//! `railsim critical-speed [SCENE]`: the hunting (critical) speed of a vehicle on straight
//! track, by ramping the speed down from a hunting limit cycle (the nonlinear critical speed) or
//! by bisecting on the growth rate of a small disturbance at constant speed
//! (`railsim_sim::stability`, docs/models/dynamics.md "Running stability").

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};

use railsim_sim::stability::{Growth, RampDown, RampResult, bisect_growth, ramp_down};
use railsim_sim::{RunOptions, Scene};

use crate::chart::{Labels, Series, line_chart};

/// The built-in scene of the study, from the repository this binary was built in.
pub const DEFAULT_SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenes/manchester_hunting.toml"
);

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum MethodName {
    /// Ramp the speed down from a hunting limit cycle: the nonlinear critical speed.
    Ramp,
    /// Bisect on the growth rate of a small disturbance at constant speeds.
    Bisect,
    /// Eigenvalues of the vehicle linearised about its centred running: the lowest speed at
    /// which an oscillatory mode loses its damping (the linear critical speed).
    Linear,
}

#[derive(Args)]
pub struct CriticalArgs {
    /// Scene file: its vehicle, track (straight, from its start), contact model, integrator and
    /// log rate are used, its speed, length and disturbance replaced; default: the built-in
    /// scenes/manchester_hunting.toml
    pub scene: Option<PathBuf>,
    /// Method.
    #[arg(long, value_enum, default_value = "ramp")]
    pub method: MethodName,
    /// Contact model instead of the scene's (e.g. `polach` for the linear method, whose
    /// linearisation STRIPES' strips make depend on the difference step).
    #[arg(long, value_enum)]
    pub model: Option<crate::ModelName>,
    /// Highest speed (km/h): ramp: the start, where the vehicle should hunt; bisect: the upper
    /// end of the bracket, where a small disturbance should grow; linear: the end of the scan.
    #[arg(long, default_value_t = 320.0)]
    pub from_kmh: f64,
    /// Lowest speed (km/h): ramp: the end of the ramp; bisect: the lower end of the bracket,
    /// where a small disturbance should decay; linear: the start of the scan, where every mode
    /// should be damped.
    #[arg(long, default_value_t = 200.0)]
    pub to_kmh: f64,
    /// Ramp: distance run at the start speed before the ramp (m).
    #[arg(long, default_value_t = 300.0)]
    pub settle_m: f64,
    /// Ramp: length of the ramp (m); the speed falls linearly with distance. Near the critical
    /// speed the oscillation decays slowly, so a ramp faster than that decay finds too low a
    /// speed: compare with a longer ramp (docs/validation.md §8).
    #[arg(long, default_value_t = 4500.0)]
    pub ramp_m: f64,
    /// Lateral offset of the leading wheelset at t = 0 (mm); default 5 mm for the ramp (to
    /// reach the large limit cycle) and 0.5 mm for the bisection (a small disturbance).
    #[arg(long, allow_hyphen_values = true)]
    pub offset_mm: Option<f64>,
    /// Ramp: hunting amplitude (mm) below which a wheelset counts as running stably (the
    /// nonlinear critical speed's; below the smallest limit cycle of interest: the Manchester
    /// vehicle has a 0.2–0.37 mm tread-contact cycle below its flange-contact cycle's fold).
    #[arg(long, default_value_t = 0.1)]
    pub threshold_mm: f64,
    /// Ramp: a larger amplitude (mm) whose branch is reported by itself: where the large
    /// (flange-contact) hunting ends.
    #[arg(long, default_value_t = 0.5)]
    pub large_threshold_mm: f64,
    /// Bisect: simulated time of each constant-speed run (s); the growth rate is taken over its
    /// second half.
    #[arg(long, default_value_t = 8.0)]
    pub duration_s: f64,
    /// Bisect, linear: stop when the bracket is narrower than this fraction of its upper speed
    /// (default 0.01 for bisect, 0.002 for linear; 1e-4 to 0.5).
    #[arg(long)]
    pub tol: Option<f64>,
    /// Linear: number of equal intervals scanned from --to-kmh to --from-kmh for the first
    /// change from damped to undamped, which is then bisected.
    #[arg(long, default_value_t = 8)]
    pub scan: usize,
    /// Linear: difference step of the positions (µm, µrad; rates ten times it per second), 0.1 to
    /// 1000; the search is repeated with four times the step as a check.
    #[arg(long, default_value_t = 1.0)]
    pub step_um: f64,
    /// Write the result as CSV: the ramp's half waves (wheelset, time, speed, amplitude), the
    /// bisection's runs (speed, growth rate, last amplitude) or the linear method's analyses
    /// (speed, real part of the least damped oscillatory mode).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Draw the result to this PNG: the ramp's bifurcation diagram (half-wave amplitude of each
    /// wheelset against speed, with the threshold), the bisection's growth rates against speed,
    /// or the linear method's least damped real part against speed.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Ramp: write the MCAP log of the ramp run here (default: no log).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Linear method only: the curve to linearise about.
    #[command(flatten)]
    pub curve: crate::modes::CurveArgs,
    /// No progress line.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run_critical(a: &CriticalArgs) -> Result<ExitCode> {
    // (before the study, which takes minutes)
    if let Some(png) = &a.png {
        crate::chart::check_png_name("--png", png)?;
    }
    if let Some(csv) = &a.csv {
        crate::check_extension("--csv", csv, &["csv"])?;
    }
    let path = a
        .scene
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_SCENE));
    for (name, v) in [
        ("--from-kmh", a.from_kmh),
        ("--to-kmh", a.to_kmh),
        ("--settle-m", a.settle_m),
        ("--ramp-m", a.ramp_m),
        ("--threshold-mm", a.threshold_mm),
        ("--large-threshold-mm", a.large_threshold_mm),
        ("--duration-s", a.duration_s),
    ] {
        if !(v.is_finite() && v > 0.0) {
            bail!(
                "{name}: expected a positive number, found {}",
                railsim_profile::short_number(v)
            );
        }
    }
    // (a bracket narrower than 1e-4 of the speed is below what the growth rates resolve, and
    // the bisection would not end)
    if let Some(t) = a.tol {
        crate::in_range("--tol", t, 1e-4, 0.5)?;
    }
    crate::check_speeds("--from-kmh", &[a.from_kmh])?;
    crate::check_speeds("--to-kmh", &[a.to_kmh])?;
    if a.to_kmh >= a.from_kmh {
        bail!(
            "--to-kmh ({}) must be below --from-kmh ({})",
            a.to_kmh,
            a.from_kmh
        );
    }
    if let Some(o) = a.offset_mm
        && !(o.is_finite() && o != 0.0)
    {
        bail!("--offset-mm: expected a non-zero number of millimetres, found {o}");
    }
    if a.scan == 0 {
        bail!("--scan: expected at least one interval, found 0");
    }
    if a.curve.radius_m.is_some() && a.method != MethodName::Linear {
        bail!("--radius-m: only the linear method (--method linear) linearises about a curve");
    }
    let mut scene = Scene::from_file(&path)?;
    if let Some(out) = &a.out {
        crate::check_log_out(out, &path, &scene)?;
    }
    if let Some(m) = a.model {
        scene.contact.model = m.into();
    }
    match a.method {
        MethodName::Ramp => ramp(a, &path, &scene),
        MethodName::Bisect => bisect(a, &scene),
        MethodName::Linear => crate::modes::linear(a, &scene),
    }
}

fn ramp(a: &CriticalArgs, path: &std::path::Path, scene: &Scene) -> Result<ExitCode> {
    let r = RampDown {
        v_start: a.from_kmh / 3.6,
        v_end: a.to_kmh / 3.6,
        settle: a.settle_m,
        ramp: a.ramp_m,
        offset: a.offset_mm.unwrap_or(5.0) * 1e-3,
        threshold: a.threshold_mm * 1e-3,
        large_threshold: a.large_threshold_mm * 1e-3,
    };
    // v dv/dx is largest at the start of the ramp
    let decel = r.v_start * (r.v_start - r.v_end) / r.ramp;
    eprintln!(
        "railsim critical-speed: {} (contact model {}): ramp-down from {} to {} km/h over {} m (deceleration {decel:.2} m/s² at its start) after {} m, leading wheelset {} mm off centre",
        scene.name,
        scene.contact.model.name(),
        a.from_kmh,
        a.to_kmh,
        a.ramp_m,
        a.settle_m,
        r.offset * 1e3
    );
    let opts = RunOptions {
        log_path: a.out.clone(),
        no_log: a.out.is_none(),
        sources: crate::run::sources(path, scene),
        ..Default::default()
    };
    let mut progress = crate::run::throttled(a.quiet, |t, t_end, w| {
        eprint!("\rt = {t:7.3} / {t_end:.3} s   real {w:7.1} s ");
    });
    let res = ramp_down(scene, &r, &opts, &mut progress).context("railsim critical-speed");
    if !a.quiet {
        eprintln!();
    }
    let res = res?;
    print_branch(&res, &r)?;
    if let Some(p) = &a.csv {
        let mut text = String::from("wheelset,t_s,speed_kmh,amplitude_mm\n");
        for (n, b) in res.branch.iter().enumerate() {
            for q in b {
                writeln!(
                    text,
                    "{n},{:.6},{:.3},{:.6}",
                    q.t,
                    q.speed * 3.6,
                    q.amplitude * 1e3
                )?;
            }
        }
        std::fs::write(p, text).with_context(|| format!("writing {}", p.display()))?;
        outln!("half waves written to {}", p.display());
    }
    if let Some(png) = &a.png {
        let mut lines: Vec<Series> = res
            .branch
            .iter()
            .enumerate()
            .map(|(n, b)| Series {
                name: crate::run::wheelset(&res.summary.wheelset_names, n as u64),
                points: b
                    .iter()
                    .filter(|p| p.t >= res.ramp_start)
                    .map(|p| (p.speed * 3.6, p.amplitude * 1e3))
                    .collect(),
            })
            .collect();
        for (what, v) in [
            ("threshold", a.threshold_mm),
            ("large", a.large_threshold_mm),
        ] {
            lines.push(Series {
                name: format!("{what} {v} mm"),
                points: vec![(a.to_kmh, v), (a.from_kmh, v)],
            });
        }
        let title = format!(
            "{} ({}): ramp-down {} -> {} km/h",
            scene.name,
            scene.contact.model.name(),
            a.from_kmh,
            a.to_kmh
        );
        line_chart(
            png,
            &Labels {
                title: &title,
                x: "speed [km/h]",
                y: "hunting amplitude per half wave [mm]",
            },
            &lines,
        )?;
        outln!("bifurcation diagram drawn to {}", png.display());
    }
    outln!(
        "simulated {:.2} s in {:.1} s ({} right-hand sides)",
        res.summary.t_end,
        res.summary.wall,
        res.summary.stats.rhs_evals
    );
    let thr = a.threshold_mm;
    match res.large_cycle_to {
        Some(v) => outln!(
            "large hunting (half waves of {} mm or more) during the ramp down to {:.1} km/h",
            a.large_threshold_mm,
            v * 3.6
        ),
        None => outln!(
            "no half wave of the ramp reached {} mm (large hunting)",
            a.large_threshold_mm
        ),
    }
    match res.critical_speed {
        None => {
            let why = if res.amplitude_at_start < r.threshold {
                format!(
                    "its amplitude before the ramp was {:.3} mm, below {thr} mm",
                    res.amplitude_at_start * 1e3
                )
            } else {
                format!(
                    "its amplitude before the ramp ({:.3} mm) was decaying ({}; a limit cycle decays no faster than {}/s)",
                    res.amplitude_at_start * 1e3,
                    rate_text(res.rate_at_start),
                    railsim_sim::stability::SUSTAINED_RATE
                )
            };
            outln!(
                "the vehicle does not hunt at {} km/h from this disturbance ({why}): no critical speed; start faster (--from-kmh), settle longer (--settle-m) or disturb more (--offset-mm)",
                a.from_kmh
            );
            Ok(ExitCode::from(1))
        }
        Some(_) if res.hunting_at_end => {
            outln!(
                "still hunting (amplitude {thr} mm or more) at the end of the ramp: the critical speed is at or below {} km/h; end lower (--to-kmh)",
                a.to_kmh
            );
            Ok(ExitCode::from(1))
        }
        Some(v) => {
            outln!(
                "nonlinear critical speed (last half wave with an amplitude of {thr} mm or more): {:.1} km/h ({:.2} m/s)",
                v * 3.6,
                v
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// A growth rate before the ramp, or why there is none.
fn rate_text(rate: Option<f64>) -> String {
    rate.map_or("unknown (fewer than four half waves)".into(), |g| {
        format!("{g:.3}/s")
    })
}

/// The branch as a table: per 10 km/h band of the ramp, the largest amplitude of each wheelset.
fn print_branch(res: &RampResult, r: &RampDown) -> Result<()> {
    outln!(
        "before the ramp at {:.1} km/h: largest amplitude {:.3} mm, growth rate {}",
        r.v_start * 3.6,
        res.amplitude_at_start * 1e3,
        rate_text(res.rate_at_start)
    );
    let band = 10.0 / 3.6;
    let n_bands = ((r.v_start - r.v_end) / band).ceil() as usize;
    // the columns named by the wheelsets' names in the vehicle file, from the front
    let names = &res.summary.wheelset_names;
    let label = |n: usize| names.get(n).map_or_else(|| format!("#{n}"), Clone::clone);
    let widths: Vec<usize> = (0..res.branch.len())
        .map(|n| (label(n).chars().count() + 3).max(7))
        .collect();
    let mut head = String::from("speed band km/h  ");
    for (n, w) in widths.iter().enumerate() {
        write!(head, "  {:>w$}", format!("{} mm", label(n)))?;
    }
    head.push_str("  ΣY rms/limit");
    outln!(
        "largest half-wave amplitude per speed band during the ramp, and the largest ratio of an \
         axle's sliding r.m.s. of the track-shift force to its EN 14363 limit (100 m windows \
         ending in the band):"
    );
    outln!("{head}");
    for k in 0..n_bands {
        let hi = r.v_start - k as f64 * band;
        let lo = (hi - band).max(r.v_end);
        let mut line = format!("{:6.1} .. {:6.1}", hi * 3.6, lo * 3.6);
        let mut any = false;
        for (b, &w) in res.branch.iter().zip(&widths) {
            let m = b
                .iter()
                .filter(|p| p.t >= res.ramp_start && p.speed <= hi && p.speed > lo)
                .map(|p| p.amplitude)
                .fold(None::<f64>, |m, x| Some(m.map_or(x, |m| m.max(x))));
            match m {
                Some(m) => {
                    any = true;
                    write!(line, "  {:w$.3}", m * 1e3)?;
                }
                None => write!(line, "  {:>w$}", "-")?,
            }
        }
        let ratio = res
            .sum_y_rms
            .iter()
            .filter(|w| w.speed <= hi && w.speed > lo)
            .map(|w| w.ratio)
            .reduce(f64::max);
        match ratio {
            Some(q) => write!(line, "  {q:13.2}")?,
            None => write!(line, "  {:>13}", "-")?,
        }
        if any || ratio.is_some() {
            outln!("{line}");
        }
    }
    let a = &res.summary.assessment;
    let band = match a.band {
        Some((lo, hi)) => format!("band-passed {lo:.2}-{hi:.2} Hz"),
        None => "no band (no instability frequency found)".to_owned(),
    };
    match (
        res.sum_y_rms_exceeded_to,
        res.sum_y_rms
            .iter()
            .max_by(|x, y| x.ratio.total_cmp(&y.ratio)),
    ) {
        (Some(v), _) => outln!(
            "EN 14363 track-shift force criterion ({band}): r.m.s. above its limit down to {:.1} km/h",
            v * 3.6
        ),
        (None, Some(w)) => outln!(
            "EN 14363 track-shift force criterion ({band}): r.m.s. below its limit throughout the \
             ramp (largest ratio {:.2} at {:.1} km/h)",
            w.ratio,
            w.speed * 3.6
        ),
        (None, None) => outln!(
            "EN 14363 track-shift force criterion: the run was shorter than one 100 m window"
        ),
    }
    Ok(())
}

fn bisect(a: &CriticalArgs, scene: &Scene) -> Result<ExitCode> {
    let offset = a.offset_mm.unwrap_or(0.5) * 1e-3;
    eprintln!(
        "railsim critical-speed: {} (contact model {}): growth rate of a {} mm disturbance at constant speed, bisected between {} and {} km/h ({} s per run)",
        scene.name,
        scene.contact.model.name(),
        offset * 1e3,
        a.to_kmh,
        a.from_kmh,
        a.duration_s
    );
    let quiet = a.quiet;
    let mut progress = |g: &Growth| {
        if !quiet {
            match g.late_rate {
                Some(r) => eprintln!(
                    "  {:7.2} km/h: growth rate over the second half {r:+.4}/s",
                    g.speed * 3.6
                ),
                None => eprintln!("  {:7.2} km/h: no growth rate", g.speed * 3.6),
            }
        }
    };
    let res = bisect_growth(
        scene,
        (a.to_kmh / 3.6, a.from_kmh / 3.6),
        a.duration_s,
        offset,
        a.tol.unwrap_or(0.01),
        &mut progress,
    )
    .context("railsim critical-speed")?;
    if let Some(p) = &a.csv {
        let mut text = String::from("speed_kmh,growth_rate_per_s,last_amplitude_mm\n");
        for g in &res.runs {
            let rate = g.late_rate.map_or(String::new(), |r| format!("{r:.6}"));
            writeln!(
                text,
                "{:.4},{rate},{:.6}",
                g.speed * 3.6,
                g.last_amplitude * 1e3
            )?;
        }
        std::fs::write(p, text).with_context(|| format!("writing {}", p.display()))?;
        outln!("runs written to {}", p.display());
    }
    if let Some(png) = &a.png {
        let mut pts: Vec<(f64, f64)> = res
            .runs
            .iter()
            .filter_map(|g| g.late_rate.map(|r| (g.speed * 3.6, r)))
            .collect();
        pts.sort_by(|p, q| p.0.total_cmp(&q.0));
        let title = format!(
            "{} ({}): growth of a {} mm disturbance",
            scene.name,
            scene.contact.model.name(),
            offset * 1e3
        );
        line_chart(
            png,
            &Labels {
                title: &title,
                x: "speed [km/h]",
                y: "growth rate [1/s]",
            },
            &[
                Series {
                    name: "growth rate".into(),
                    points: pts,
                },
                Series {
                    name: "zero".into(),
                    points: vec![(a.to_kmh, 0.0), (a.from_kmh, 0.0)],
                },
            ],
        )?;
        outln!("growth rates drawn to {}", png.display());
    }
    outln!(
        "critical speed (growth rate of a {} mm disturbance changes sign): {:.1} km/h ({:.2} m/s), {} runs",
        offset * 1e3,
        res.critical_speed * 3.6,
        res.critical_speed,
        res.runs.len()
    );
    Ok(ExitCode::SUCCESS)
}
