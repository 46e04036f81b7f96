//! `railsim replay LOG`: lists a log's channels, scene and statistics, exports topics to CSV and
//! plots signals to PNG. Reading, flattening and units come from `railsim_log`; this module only
//! chooses what to read, formats it and draws it.

use std::collections::HashMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, anyhow, bail};

use crate::chart::{Labels, Series, bounds, check_png_name, line_chart};
use clap::Args;

use railsim_log::export::{
    Scalar, csv_file_name, export_csv, export_csv_files, flatten_json, summarize, units_of,
};
use railsim_log::{LogError, LogReader, Query, ns_to_s, s_to_ns};
use railsim_profile::short_number;

#[derive(Args)]
pub struct ReplayArgs {
    /// The MCAP log written by `railsim run` (a log cut short by a killed run is read up to its
    /// last complete chunk).
    log: PathBuf,
    /// Topics to list or export, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    topics: Vec<String>,
    /// Start of the time range (s), inclusive.
    #[arg(long)]
    from_s: Option<f64>,
    /// End of the time range (s), inclusive.
    #[arg(long)]
    to_s: Option<f64>,
    /// Export to CSV: a directory (one `<topic>.csv` per topic, created if needed) or a single
    /// `.csv` file (exactly one topic).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Signals to plot against time, comma-separated, each `topic:field.path`, e.g.
    /// `/wheelsets/0:y_over_q_left` or `/bodies/wheelset_0:position.1`.
    #[arg(long, value_delimiter = ',', requires = "png")]
    plot: Vec<String>,
    /// The PNG file the plot is written to.
    #[arg(long, requires = "plot")]
    png: Option<PathBuf>,
    /// Plot the `--plot` signals against this signal instead of time (`topic:field.path`, one
    /// message per time), e.g. a friction element's force against its deflection:
    /// `--plot /elements/rubbing:force_n.2 --against /elements/rubbing:deflection_m.2`.
    #[arg(long, requires = "plot")]
    against: Option<String>,
    /// Re-run the scene stored in the log (its scene, vehicle and track files must be unchanged
    /// on disk) and report whether the re-run's state digest equals the logged one (exit 1 if
    /// not). Not with the listing, export or plot options.
    #[arg(long, conflicts_with_all = ["topics", "from_s", "to_s", "csv", "plot", "png", "against"])]
    rerun: bool,
}

/// Re-run the scene a log stores and compare state digests.
fn rerun(reader: &railsim_log::LogReader) -> Result<ExitCode> {
    let meta = reader.metadata();
    let sources = meta.get("railsim_sources").ok_or_else(|| {
        anyhow::anyhow!("the log stores no scene sources (not written by `railsim run`)")
    })?;
    let logged = meta
        .get("railsim_result")
        .and_then(|m| m.get("state_digest"))
        .ok_or_else(|| anyhow::anyhow!("the log has no state digest (the run did not finish)"))?;
    for key in ["scene", "vehicle", "track"] {
        let (Some(path), Some(text)) = (sources.get(&format!("{key}_path")), sources.get(key))
        else {
            anyhow::bail!("the log does not store the {key} file");
        };
        let now = std::fs::read_to_string(path)
            .with_context(|| format!("reading the {key} file {path} named in the log"))?;
        if &now != text {
            anyhow::bail!(
                "the {key} file {path} changed since the log was written; cannot re-run it as logged"
            );
        }
    }
    // The data files (a log written before stop 40 lists none): each must read as it did.
    let data = sources
        .get(crate::run::DATA_FILES)
        .map_or("", String::as_str);
    for line in data.lines() {
        let Some((logged, path)) = line.split_once(' ') else {
            anyhow::bail!(
                "the log's {} line {line:?} is not `<digest> <path>`",
                crate::run::DATA_FILES
            );
        };
        let bytes = std::fs::read(path)
            .with_context(|| format!("reading the data file {path} named in the log"))?;
        let now = crate::run::file_digest(&bytes);
        if now != logged {
            anyhow::bail!(
                "the data file {path} changed since the log was written ({now}, logged {logged}); cannot re-run it as logged"
            );
        }
    }
    let scene_path = PathBuf::from(&sources["scene_path"]);
    let mut scene = railsim_sim::Scene::from_file(&scene_path)?;
    if let Some(note) = assess_as_logged(reader.scene(), &mut scene) {
        eprintln!("note: {note}");
    }
    let result = &meta["railsim_result"];
    let mut sim = railsim_sim::Simulation::new(&scene)?;
    // A stopped run is re-run to its scene's end, where it must stop again; a finished one to
    // the time it ended (a run shortened with --duration-s).
    let stopped = result.get("outcome").is_some_and(|o| o == "stopped");
    let opts = railsim_sim::RunOptions {
        no_log: true,
        t_end: if stopped {
            None
        } else {
            result.get("t_end_s").and_then(|t| t.parse::<f64>().ok())
        },
        ..Default::default()
    };
    let (digest, what) = match (sim.run(&scene, &opts, &mut |_, _| {}, &mut |_| {}), stopped) {
        (Ok(summary), false) => (summary.digest, format!("{:.3} s simulated", summary.t_end)),
        (
            Err(railsim_sim::SimError::Stopped {
                t,
                body,
                quantity,
                digest: Some(d),
                ..
            }),
            true,
        ) => (d, format!("stopped at t = {t:.6} s: {body}: {quantity}")),
        (Ok(summary), true) => {
            outln!(
                "re-ran {}: it ran to its end at {:.3} s, where the log stopped at t = {} s",
                scene_path.display(),
                summary.t_end,
                result.get("stop_t_s").map_or("?", String::as_str)
            );
            outln!("the re-run DIFFERS from the log");
            return Ok(ExitCode::from(1));
        }
        (Err(e), _) => return Err(e.into()),
    };
    let digest = format!("{digest:016x}");
    outln!(
        "re-ran {} ({what}): state digest {digest}, logged {logged}",
        scene_path.display()
    );
    if &digest == logged {
        outln!("the re-run agrees with the log: identical states at every sample");
        Ok(ExitCode::SUCCESS)
    } else {
        outln!("the re-run DIFFERS from the log");
        Ok(ExitCode::from(1))
    }
}

/// A log written before stop 33 records no `assessment_rate_hz`: its run sampled at the log rate,
/// where a scene without `[assessment] rate_hz` is now assessed at 1 or 2 kHz between the log's
/// samples (docs/models/dynamics.md, "Aliasing"). Such a scene is re-run at its log rate, as it
/// was, with a note saying so.
fn assess_as_logged(
    logged: Option<&std::collections::BTreeMap<String, String>>,
    scene: &mut railsim_sim::Scene,
) -> Option<String> {
    let before_stop_33 = logged.is_some_and(|m| !m.contains_key("assessment_rate_hz"));
    if !before_stop_33 || scene.assessment.rate_hz.is_some() {
        return None;
    }
    let now = scene.assessment_rate();
    scene.sample_at_log_rate();
    Some(format!(
        "the log records no assessment rate (written before stop 33, when runs were sampled at \
         the log rate): re-running at the log's {} Hz, not the {now} Hz a run of the scene now \
         takes",
        scene.log.rate_hz
    ))
}

pub fn run_replay(a: &ReplayArgs) -> Result<ExitCode> {
    if let Some(png) = &a.png {
        check_png_name("--png", png)?;
    }
    let reader = open_log(&a.log)?;
    if let Some(note) = reader.truncation() {
        eprintln!(
            "railsim: warning: {} was read without its summary: {note}",
            a.log.display()
        );
    }
    let version = reader
        .metadata()
        .get(railsim_log::FORMAT_METADATA)
        .and_then(|m| m.get("format_version"));
    if version.is_some_and(|v| v == "1") {
        eprintln!(
            "railsim: warning: {} is in log format 1 (before stop 26): its wheelsets' \
             angular_velocity lacks the spin about the axle, and its bodies rested at the \
             vehicle's unloaded geometry (docs/formats/log.md)",
            a.log.display()
        );
    }
    let range = time_range(a.from_s, a.to_s)?;
    // A range that misses the log's messages would list or export nothing, silently.
    if let Some((first, last)) = reader.time_range()
        && (range.0.is_some_and(|f| f > last) || range.1.is_some_and(|t| t < first))
    {
        bail!(
            "--from-s/--to-s: the time range misses the log, whose messages run from {} to {} s",
            short_number(ns_to_s(first)),
            short_number(ns_to_s(last))
        );
    }
    check_topics(&reader, &a.topics)?;
    let mut query = if a.topics.is_empty() {
        Query::all()
    } else {
        Query::topics(a.topics.iter().cloned())
    };
    query.start_ns = range.0;
    query.end_ns = range.1;

    let mut did_something = false;
    if a.rerun {
        return rerun(&reader);
    }
    if let Some(out) = &a.csv {
        crate::check_not_input("--csv", out, &[&a.log])?;
        if out.extension().is_some() && !out.is_dir() {
            crate::check_extension("--csv", out, &["csv"])?;
        }
        write_csv(&reader, &query, out)?;
        did_something = true;
    }
    if let Some(png) = &a.png {
        plot(&reader, &a.plot, a.against.as_deref(), range, png)?;
        did_something = true;
    }
    if !did_something {
        list(&reader, &query)?;
    }
    Ok(ExitCode::SUCCESS)
}

fn open_log(path: &Path) -> Result<LogReader> {
    LogReader::open(path).map_err(|e| match e {
        LogError::Corrupt { what, .. } if what.starts_with("the file starts with") => anyhow!(
            "{}: not an MCAP file ({what}; an MCAP log starts with the bytes \\x89MCAP0\\r\\n)",
            path.display()
        ),
        other => other.into(),
    })
}

/// `--from-s` / `--to-s` as an inclusive nanosecond range.
fn time_range(from_s: Option<f64>, to_s: Option<f64>) -> Result<(Option<u64>, Option<u64>)> {
    let to_ns = |name: &str, t: Option<f64>| -> Result<Option<u64>> {
        t.map(|t| {
            s_to_ns(t).ok_or_else(|| {
                anyhow!(
                    "{name}: expected a time from 0 to {:.2e} s (the range of the log's \
                     nanosecond clock), found {}",
                    u64::MAX as f64 * 1e-9,
                    short_number(t)
                )
            })
        })
        .transpose()
    };
    let from = to_ns("--from-s", from_s)?;
    let to = to_ns("--to-s", to_s)?;
    if let (Some(f), Some(t)) = (from, to)
        && f > t
    {
        bail!(
            "--from-s {} is after --to-s {}",
            short_number(from_s.unwrap_or_default()),
            short_number(to_s.unwrap_or_default())
        );
    }
    Ok((from, to))
}

fn available_topics(reader: &LogReader) -> String {
    let topics: Vec<&str> = reader.channels().iter().map(|c| c.topic.as_str()).collect();
    if topics.is_empty() {
        "the log has no channels".to_owned()
    } else {
        format!("the log has: {}", topics.join(", "))
    }
}

fn check_topics(reader: &LogReader, topics: &[String]) -> Result<()> {
    for topic in topics {
        if reader.channel(topic).is_none() {
            bail!(
                "{}: unknown topic '{topic}'; {}",
                reader.path().display(),
                available_topics(reader)
            );
        }
    }
    Ok(())
}

/// A number in a column: fixed-point in a readable range, exponent otherwise.
fn num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 {
        "0".to_owned()
    } else if (1e-3..1e6).contains(&a) {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0');
        s.trim_end_matches('.').to_owned()
    } else {
        let s = format!("{x:.6e}");
        match s.split_once('e') {
            Some((mantissa, exp)) if mantissa.contains('.') => {
                let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
                format!("{mantissa}e{exp}")
            }
            _ => s,
        }
    }
}

fn seconds(t_ns: Option<u64>) -> String {
    t_ns.map_or_else(|| "-".to_owned(), |t| format!("{:.6}", ns_to_s(t)))
}

/// Prints rows as left-aligned first columns and right-aligned numeric columns.
fn print_table(header: &[&str], rows: &[Vec<String>], left: usize, indent: &str) -> Result<()> {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| -> Result<()> {
        let mut s = String::from(indent);
        for (i, (cell, w)) in cells.zip(&widths).enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            let pad = w - cell.chars().count();
            if i < left {
                s.push_str(cell);
                s.push_str(&" ".repeat(pad));
            } else {
                s.push_str(&" ".repeat(pad));
                s.push_str(cell);
            }
        }
        outln!("{}", s.trim_end());
        Ok(())
    };
    line(&mut header.iter().copied())?;
    for row in rows {
        line(&mut row.iter().map(String::as_str))?;
    }
    Ok(())
}

fn list(reader: &LogReader, query: &Query) -> Result<()> {
    let status = if reader.is_complete() {
        "finished"
    } else {
        "read without its summary, up to its last complete chunk"
    };
    outln!(
        "log {} ({status}): {} messages on {} channels",
        reader.path().display(),
        reader.message_count(),
        reader.channels().len()
    );
    match reader.time_range() {
        Some((first, last)) => outln!(
            "time {} s to {} s",
            seconds(Some(first)),
            seconds(Some(last))
        ),
        None => outln!("no messages"),
    }
    outln!("{}", outcome(reader));
    match reader.scene() {
        Some(scene) => {
            let name = scene.get("name").map_or("(unnamed)", String::as_str);
            outln!("scene {name}: {} keys", scene.len());
            let width = scene.keys().map(|k| k.chars().count()).max().unwrap_or(0);
            for (k, v) in scene {
                let mut v = v.replace('\n', " ");
                if v.chars().count() > 70 {
                    v = v.chars().take(67).collect::<String>() + "...";
                }
                outln!("  {k:<width$} = {v}");
            }
        }
        None => outln!("scene: none recorded"),
    }
    if let Some(toml) = reader.scene_toml()? {
        outln!("scene TOML attached ({} bytes)", toml.len());
    }

    outln!();
    outln!("channels:");
    let rows: Vec<Vec<String>> = reader
        .channels()
        .iter()
        .filter(|c| query.topics.as_ref().is_none_or(|t| t.contains(&c.topic)))
        .map(|c| {
            vec![
                c.topic.clone(),
                c.schema_name.clone(),
                c.message_count.to_string(),
                seconds(c.first_ns),
                seconds(c.last_ns),
            ]
        })
        .collect();
    print_table(
        &["topic", "schema", "messages", "first[s]", "last[s]"],
        &rows,
        2,
        "  ",
    )?;

    let stats = summarize(reader, query)?;
    outln!();
    match (query.start_ns, query.end_ns) {
        (None, None) => outln!("statistics (numeric fields):"),
        (s, e) => outln!(
            "statistics (numeric fields) from {} s to {} s:",
            s.map_or("start".to_owned(), |t| format!("{}", ns_to_s(t))),
            e.map_or("end".to_owned(), |t| format!("{}", ns_to_s(t)))
        ),
    }
    for topic in &stats {
        outln!();
        outln!(
            "{} ({}, {} messages)",
            topic.topic,
            topic.schema_name,
            topic.messages
        );
        if topic.fields.is_empty() {
            outln!("  no numeric fields in range");
            continue;
        }
        let rows: Vec<Vec<String>> = topic
            .fields
            .iter()
            .map(|f| {
                vec![
                    f.path.clone(),
                    f.unit.clone().unwrap_or_default(),
                    num(f.min),
                    num(f.max),
                    num(f.mean),
                ]
            })
            .collect();
        print_table(&["field", "unit", "min", "max", "mean"], &rows, 2, "  ")?;
    }
    Ok(())
}

/// How the run that wrote the log ended, from its `railsim_result` record (the scene's
/// `run_to_s`, listed with the scene, is where the run was to end, not where it did).
fn outcome(reader: &LogReader) -> String {
    let Some(result) = reader.metadata().get("railsim_result") else {
        return "run: no result recorded (the run did not close its log)".to_owned();
    };
    let get = |k: &str| result.get(k).map_or("?", String::as_str);
    let t_end = result
        .get("t_end_s")
        .and_then(|t| t.parse::<f64>().ok())
        .map_or("?".to_owned(), short_number);
    match result.get("outcome").map(String::as_str) {
        Some("stopped") => format!(
            "run: STOPPED at t = {} s: {}: {}",
            // as the run's error message gives it
            result
                .get("stop_t_s")
                .and_then(|t| t.parse::<f64>().ok())
                .map_or("?".to_owned(), |t| format!("{t:.6}")),
            get("stop_body"),
            get("stop_quantity")
        ),
        Some("failed") => format!("run: FAILED at t = {t_end} s: {}", get("message")),
        // logs written before the outcome was recorded (stop 27) name no outcome
        Some("finished") | None => format!(
            "run: ended at t = {t_end} s, state digest {}",
            get("state_digest")
        ),
        Some(other) => format!("run: outcome '{other}' at t = {t_end} s"),
    }
}

fn write_csv(reader: &LogReader, query: &Query, out: &Path) -> Result<()> {
    let is_file = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
        && !out.is_dir();
    let range = match (query.start_ns, query.end_ns) {
        (None, None) => None,
        (s, e) => Some((s.unwrap_or(0), e.unwrap_or(u64::MAX))),
    };
    if is_file {
        let topic = match &query.topics {
            Some(t) if t.len() == 1 => t[0].clone(),
            Some(t) => bail!(
                "--csv {}: a single CSV file holds one topic, {} were given; give a directory \
                 for one file per topic",
                out.display(),
                t.len()
            ),
            None if reader.channels().len() == 1 => reader.channels()[0].topic.clone(),
            None => bail!(
                "--csv {}: a single CSV file holds one topic; choose one with --topics ({}) or \
                 give a directory for one file per topic",
                out.display(),
                available_topics(reader)
            ),
        };
        let file = File::create(out).with_context(|| format!("creating {}", out.display()))?;
        let export = export_csv(reader, &topic, range, file)?;
        outln!("{topic}: {} rows to {}", export.rows, out.display());
        return Ok(());
    }
    // Two topics that map to one file name would overwrite each other: refuse before writing.
    let topics: Vec<&str> = match &query.topics {
        Some(t) => t.iter().map(String::as_str).collect(),
        None => reader.channels().iter().map(|c| c.topic.as_str()).collect(),
    };
    let mut seen = HashMap::new();
    for topic in topics {
        if let Some(other) = seen.insert(csv_file_name(topic), topic) {
            bail!(
                "--csv {}: topics '{other}' and '{topic}' both map to {}; export them one at a time",
                out.display(),
                csv_file_name(topic)
            );
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let written = export_csv_files(reader, query, out)?;
    for (topic, file, rows) in &written {
        outln!("{topic}: {rows} rows to {}", file.display());
    }
    Ok(())
}

/// One requested signal and the samples read for it.
struct Signal {
    topic: String,
    field: String,
    unit: Option<String>,
    /// Samples per line. Topics such as `/contact/0/left` carry one message per patch at each
    /// time: each patch (by the message's `patch` field, else by its rank among the messages of
    /// one time) becomes its own line.
    series: Vec<Vec<(f64, f64)>>,
    /// Whether lines are told apart by a `patch` field (else by rank within a time).
    by_patch: bool,
}

fn parse_signal(reader: &LogReader, spec: &str) -> Result<Signal> {
    let Some((topic, field)) = spec.rsplit_once(':') else {
        bail!(
            "--plot: expected topic:field.path, found \"{spec}\" (e.g. /wheelsets/0:y_over_q_left)"
        );
    };
    if field.is_empty() {
        bail!("--plot: \"{spec}\" names no field after the ':'");
    }
    let channel = reader.channel(topic).ok_or_else(|| {
        anyhow!(
            "{}: --plot {spec}: unknown topic '{topic}'; {}",
            reader.path().display(),
            available_topics(reader)
        )
    })?;
    if channel.message_count == 0 {
        bail!(
            "{}: --plot {spec}: the log has no messages on topic '{topic}'",
            reader.path().display()
        );
    }
    let units = units_of(channel);
    let unit_key: Vec<&str> = field
        .split('.')
        .filter(|p| p.parse::<usize>().is_err())
        .collect();
    Ok(Signal {
        topic: topic.to_owned(),
        field: field.to_owned(),
        unit: units.get(&unit_key.join(".")).cloned(),
        series: Vec::new(),
        by_patch: false,
    })
}

fn read_signal(
    reader: &LogReader,
    signal: &mut Signal,
    range: (Option<u64>, Option<u64>),
) -> Result<()> {
    let mut query = Query::topics([signal.topic.as_str()]);
    query.start_ns = range.0;
    query.end_ns = range.1;
    let mut last_t: Option<u64> = None;
    let mut index = 0usize;
    // the fields of the messages without the signal's (a field a topic carries only at times,
    // as a patch's `weight` in a rail transition, leaves a gap there); an error if no message
    // has it
    let mut fields_seen: Vec<String> = Vec::new();
    let mut found = false;
    let path = reader.path().to_path_buf();
    reader.for_each(&query, |m| {
        let fields = flatten_json(m.data).map_err(|e| LogError::Export {
            path: path.clone(),
            message: format!(
                "message on '{}' at t = {} ns is not JSON: {e}",
                signal.topic, m.log_time_ns
            ),
        })?;
        index = if last_t == Some(m.log_time_ns) {
            index + 1
        } else {
            0
        };
        last_t = Some(m.log_time_ns);
        let patch = fields.iter().find_map(|(p, v)| match v {
            Scalar::Number(x) if p == "patch" && *x >= 0.0 && x.fract() == 0.0 => Some(*x as usize),
            _ => None,
        });
        signal.by_patch |= patch.is_some();
        let index = patch.unwrap_or(index);
        let field = fields.iter().find(|(p, _)| *p == signal.field);
        found |= field.is_some();
        match field {
            Some((_, Scalar::Number(y))) => {
                if signal.series.len() <= index {
                    signal.series.resize_with(index + 1, Vec::new);
                }
                signal.series[index].push((ns_to_s(m.log_time_ns), *y));
            }
            // A non-finite value is logged as null: leave a gap rather than fail.
            Some((_, Scalar::Null)) => {}
            Some((_, other)) => {
                return Err(LogError::Export {
                    path: path.clone(),
                    message: format!(
                        "field '{}' of '{}' is not numeric (found \"{other}\")",
                        signal.field, signal.topic
                    ),
                });
            }
            None => {
                if !found {
                    for (p, _) in fields {
                        if !fields_seen.contains(&p) {
                            fields_seen.push(p);
                        }
                    }
                }
            }
        }
        Ok(())
    })?;
    if !found && !fields_seen.is_empty() {
        bail!(
            "{}: unknown field '{}' on topic '{}'; its fields are: {}",
            reader.path().display(),
            signal.field,
            signal.topic,
            fields_seen.join(", ")
        );
    }
    Ok(())
}

fn plot(
    reader: &LogReader,
    specs: &[String],
    against: Option<&str>,
    range: (Option<u64>, Option<u64>),
    png: &Path,
) -> Result<()> {
    let mut signals = Vec::new();
    for spec in specs {
        signals.push(parse_signal(reader, spec)?);
    }
    for signal in &mut signals {
        read_signal(reader, signal, range)?;
    }
    let abscissa = match against {
        Some(spec) => {
            let mut x = parse_signal(reader, spec)?;
            read_signal(reader, &mut x, range)?;
            if x.series.len() != 1 {
                bail!(
                    "--against {spec}: the topic has {} messages at a time; expected one (a signal to plot against)",
                    x.series.len()
                );
            }
            for signal in &mut signals {
                for series in &mut signal.series {
                    *series = against_signal(series, &x.series[0]);
                }
            }
            Some(x)
        }
        None => None,
    };
    // one chart line per signal and message slot
    let mut lines = Vec::new();
    for signal in &signals {
        let several = signal.series.len() > 1;
        for (k, series) in signal.series.iter().enumerate() {
            let name = if signal.by_patch && (several || k > 0) {
                format!("{} patch {k}", label(signal))
            } else if several {
                format!("{} (message {k} at each time)", label(signal))
            } else {
                label(signal)
            };
            lines.push(Series {
                name,
                points: series.clone(),
            });
        }
    }
    let Some(([x0, x1], _)) = bounds(&lines) else {
        bail!(
            "--plot: no samples of {} in the chosen time range{}",
            specs.join(", "),
            against.map_or(String::new(), |a| format!(" at the times of {a}"))
        );
    };
    let units: Vec<Option<&str>> = signals.iter().map(|s| s.unit.as_deref()).collect();
    let y_label = if signals.len() == 1 {
        label(&signals[0])
    } else if units.iter().all(|u| *u == units[0]) {
        format!("value [{}]", units[0].unwrap_or("1"))
    } else {
        "value (units in the legend)".to_owned()
    };
    let title = match reader.scene().and_then(|s| s.get("name")) {
        Some(name) => format!("scene {name}: {}", file_name(reader.path())),
        None => file_name(reader.path()),
    };
    let x_label = abscissa.as_ref().map_or("time [s]".to_owned(), label);
    line_chart(
        png,
        &Labels {
            title: &title,
            x: &x_label,
            y: &y_label,
        },
        &lines,
    )?;
    let samples: usize = signals
        .iter()
        .flat_map(|s| s.series.iter().map(Vec::len))
        .sum();
    match &abscissa {
        None => outln!(
            "plotted {} signal(s), {samples} samples, {} s to {} s, to {}",
            signals.len(),
            num(x0),
            num(x1),
            png.display()
        ),
        Some(x) => outln!(
            "plotted {} signal(s) against {}, {samples} samples, {} to {}, to {}",
            signals.len(),
            label(x),
            num(x0),
            num(x1),
            png.display()
        ),
    }
    Ok(())
}

/// The points `(t, y)` of `series` as `(x(t), y)`, with `x` sampled at the same times (both
/// read from one log, so equal times are equal numbers); points without an `x` are left out.
fn against_signal(series: &[(f64, f64)], x: &[(f64, f64)]) -> Vec<(f64, f64)> {
    series
        .iter()
        .filter_map(|&(t, y)| {
            x.binary_search_by(|(tx, _)| tx.total_cmp(&t))
                .ok()
                .map(|i| (x[i].1, y))
        })
        .collect()
}

fn label(signal: &Signal) -> String {
    match &signal.unit {
        Some(u) => format!("{}:{} [{u}]", signal.topic, signal.field),
        None => format!("{}:{}", signal.topic, signal.field),
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log without `assessment_rate_hz` (before stop 33) re-runs its scene at the log rate; a
    /// log with it, or a scene that sets its own rate, is re-run as it is.
    #[test]
    fn a_log_from_before_stop_33_is_re_run_at_its_log_rate() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/default.toml");
        let scene = railsim_sim::Scene::from_file(path).unwrap();
        assert_eq!(scene.assessment.rate_hz, None);
        let old = std::collections::BTreeMap::from([("log_rate_hz".to_owned(), "200".to_owned())]);
        let mut new = old.clone();
        new.insert("assessment_rate_hz".to_owned(), "1000".to_owned());
        let mut s = scene.clone();
        let note = assess_as_logged(Some(&old), &mut s).expect("a note");
        assert!(
            note.contains("at the log's 200 Hz, not the 1000 Hz"),
            "{note}"
        );
        assert_eq!(s.assessment_rate(), 200.0);
        for logged in [Some(&new), None] {
            let mut s = scene.clone();
            assert_eq!(assess_as_logged(logged, &mut s), None);
            assert_eq!(s.assessment_rate(), 1000.0);
        }
        let mut own = scene.clone();
        own.assessment.rate_hz = Some(400.0);
        assert_eq!(assess_as_logged(Some(&old), &mut own), None);
        assert_eq!(own.assessment_rate(), 400.0);
    }
}
