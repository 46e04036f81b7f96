//! `TrackModel`: the compiled, immutable track (SI, checked), and its evaluation.

use std::ops::Range;
use std::path::{Path, PathBuf};

use railsim_spec::short_number;
use toml::Spanned;

use crate::alignment::{
    Alignment, Segment, SegmentInput, SegmentKind, TrackFrame, TransitionShape,
};
use crate::error::{Sink, TrackError, TrackErrors};
use crate::irregularity::{
    self, Irregularity, IrregularitySeries, Spectrum, SyntheticParams, default_components,
};
use crate::spec::{IrregularitySpec, RailProfileSpec, SegmentSpec, TrackSpec};

/// \[m\] hard lower limit of a curve radius.
pub const HARD_MIN_RADIUS_M: f64 = 50.0;
/// \[mm\] largest cant accepted.
pub const MAX_CANT_MM: f64 = 200.0;
/// \[‰\] steepest gradient accepted.
pub const MAX_GRADIENT_PERMILLE: f64 = 100.0;
/// \[m\] longest tangent or circular curve accepted (a longer one is a unit or data error).
pub const MAX_SEGMENT_LENGTH_M: f64 = 1e6;
/// \[m\] longest transition accepted: real transitions are at most a few hundred metres, and a
/// transition's geometry is integrated along its length when the track is built.
pub const MAX_TRANSITION_LENGTH_M: f64 = 1e4;

/// Built-in rail profile names.
pub const BUILTIN_RAIL_PROFILES: [&str; 1] = ["uic60"];

/// A rail profile reference, resolved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RailProfile {
    /// The built-in UIC60 (60E1) profile of `railsim-profile`.
    Uic60,
    /// A profile file (path resolved relative to the track file; it exists).
    File(PathBuf),
}

/// Elastic rail support: under each wheel a rail mass that moves along the track with the
/// wheelset, held by a spring and a damper in parallel laterally and vertically (the track's
/// frame). SI units. Rigid rails when the track has none (`docs/models/track.md`, "Elastic rail
/// support").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailSupport {
    /// \[kg\] rail mass under each wheel
    pub mass: f64,
    /// \[N/m\] lateral stiffness per wheel
    pub lateral_stiffness: f64,
    /// \[N s/m\] lateral damping per wheel
    pub lateral_damping: f64,
    /// \[N/m\] vertical stiffness per wheel
    pub vertical_stiffness: f64,
    /// \[N s/m\] vertical damping per wheel
    pub vertical_damping: f64,
}

/// Options the caller adds to a compile (e.g. a vehicle's limit on curve radius).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompileOptions {
    /// \[m\] reject curves tighter than this (the larger of this and the file's
    /// `min_radius_m` applies; never below [`HARD_MIN_RADIUS_M`]).
    pub min_radius: f64,
}

impl Default for CompileOptions {
    fn default() -> Self {
        CompileOptions {
            min_radius: HARD_MIN_RADIUS_M,
        }
    }
}

/// The compiled track: immutable, SI, shareable between threads.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackModel {
    name: String,
    source: String,
    gauge: f64,
    /// From s = 0 (the top-level keys), then the `[[rail_section]]`s in track order.
    rail_sections: Vec<RailSection>,
    alignment: Alignment,
    irregularities: Option<IrregularitySeries>,
    /// The CSV file of `measured` irregularities (resolved; it was read).
    irregularity_file: Option<PathBuf>,
    rail_support: Option<RailSupport>,
}

fn span_of<T>(v: &Spanned<T>) -> Range<usize> {
    v.span()
}

/// The span of a segment's `key` where it is given, else of its `type` (the segment's place).
fn key_or_kind<T, U>(key: &Option<Spanned<T>>, kind: &Spanned<U>) -> Range<usize> {
    key.as_ref().map_or_else(|| kind.span(), span_of)
}

/// Parse `"1:N"` (or `"none"`) into an angle.
fn parse_inclination(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("none") {
        return Some(0.0);
    }
    let (a, b) = t.split_once(':')?;
    let a: f64 = a.trim().parse().ok()?;
    let b: f64 = b.trim().parse().ok()?;
    if a == 1.0 && b.is_finite() && (5.0..=1000.0).contains(&b) {
        Some((1.0 / b).atan())
    } else {
        None
    }
}

impl TrackModel {
    /// Read and compile a track file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<TrackModel, TrackErrors> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| TrackError::Io {
            file: name.clone(),
            message: e.to_string(),
        })?;
        let spec = TrackSpec::from_toml_str(&text, &name)?;
        TrackModel::compile(&spec, &name)
    }

    /// Compile a spec with default options. `source_name` is the path of the track file: it
    /// prefixes every message and relative file names are resolved from its directory.
    ///
    /// ```
    /// use railsim_track::{TrackModel, TrackSpec};
    /// let text = r#"
    /// gauge_mm = 1435
    /// rail_inclination = "1:40"
    /// rail_profile = { left = "uic60", right = "uic60" }
    /// [[segment]]
    /// type = "tangent"
    /// length_m = 100
    /// [[segment]]
    /// type = "clothoid"
    /// length_m = 60
    /// [[segment]]
    /// type = "curve"
    /// radius_m = 1200
    /// cant_mm = 100
    /// direction = "left"
    /// length_m = 200
    /// "#;
    /// let spec = TrackSpec::from_toml_str(text, "doc.toml").unwrap();
    /// let track = TrackModel::compile(&spec, "doc.toml").unwrap();
    /// assert_eq!(track.length(), 360.0);
    /// let f = track.frame_at(300.0);
    /// assert!((f.curvature - 1.0 / 1200.0).abs() < 1e-15);
    /// ```
    pub fn compile(spec: &TrackSpec, source_name: &str) -> Result<TrackModel, TrackErrors> {
        TrackModel::compile_with(spec, source_name, &CompileOptions::default())
    }

    /// Compile a spec, reporting every problem found with `file:line:col`.
    pub fn compile_with(
        spec: &TrackSpec,
        source_name: &str,
        options: &CompileOptions,
    ) -> Result<TrackModel, TrackErrors> {
        let mut sink = Sink::new(source_name, &spec.source);
        let dir = Path::new(source_name)
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();

        // Gauge.
        let gauge_mm = *spec.gauge_mm.get_ref();
        check_gauge(&mut sink, &spec.gauge_mm, "", None);
        // Rail inclination and profiles, from s = 0 and in every rail section.
        let incl = check_inclination(&mut sink, &spec.rail_inclination, "");
        let profiles = check_rail_profiles(&mut sink, &spec.rail_profile, &dir, "");
        // Cant base.
        let cant_base_mm = match &spec.cant_base_mm {
            Some(v) => {
                let b = *v.get_ref();
                if !(b.is_finite() && b >= gauge_mm && b <= gauge_mm + 300.0) {
                    sink.invalid(
                        &span_of(v),
                        "cant_base_mm",
                        format!(
                            "cant_base_mm = {} must be between gauge_mm and gauge_mm + 300",
                            short_number(b)
                        ),
                    );
                }
                b
            }
            None => gauge_mm + 65.0,
        };
        // Minimum radius.
        let mut min_radius = options.min_radius.max(HARD_MIN_RADIUS_M);
        if let Some(v) = &spec.min_radius_m {
            let r = *v.get_ref();
            if !(r.is_finite() && r >= HARD_MIN_RADIUS_M) {
                sink.invalid(
                    &span_of(v),
                    "min_radius_m",
                    format!("min_radius_m = {r} must be at least {HARD_MIN_RADIUS_M}"),
                );
            } else {
                min_radius = min_radius.max(r);
            }
        }
        let vertical_radius = match &spec.vertical_curve_radius_m {
            Some(v) => {
                let r = *v.get_ref();
                if !(r.is_finite() && r >= 100.0) {
                    sink.invalid(
                        &span_of(v),
                        "vertical_curve_radius_m",
                        format!("vertical_curve_radius_m = {r} must be at least 100"),
                    );
                    None
                } else {
                    Some(r)
                }
            }
            None => None,
        };

        // Segments.
        if spec.segment.is_empty() {
            sink.invalid(
                &(0..0),
                "segment",
                "segment: the track needs at least one [[segment]] (tangent, clothoid, bloss, cosine or curve)"
                    .to_owned(),
            );
        }
        let mut inputs: Vec<SegmentInput> = Vec::with_capacity(spec.segment.len());
        for (i, seg) in spec.segment.iter().enumerate() {
            inputs.push(check_segment(&mut sink, i + 1, seg, min_radius));
        }
        // Transitions take curvature and cant from their neighbours; two adjacent transitions
        // meet at zero curvature and cant (a reverse curve's inflection: a transition's own
        // values are zero until it is given its neighbours').
        let n = inputs.len();
        for i in 0..n {
            if !matches!(inputs[i].kind, SegmentKind::Transition(_)) {
                continue;
            }
            let prev = if i > 0 { Some(inputs[i - 1]) } else { None };
            let next = inputs.get(i + 1).copied();
            let k0 = prev.map_or(0.0, |p| p.curvature.1);
            let c0 = prev.map_or(0.0, |p| p.cant.1);
            let k1 = next.map_or(0.0, |p| p.curvature.0);
            let c1 = next.map_or(0.0, |p| p.cant.0);
            inputs[i].curvature = (k0, k1);
            inputs[i].cant = (c0, c1);
        }
        // The cant must not step at a join: a step rolls the track, and every body as its frame
        // passes, at once (the frame's orientation jumps; docs/models/dynamics.md, "Kinks").
        for i in 1..n {
            let (before, after) = (inputs[i - 1].cant.1, inputs[i].cant.0);
            if (after - before).abs() > 1e-9 {
                let seg = spec.segment[i].get_ref();
                let span = key_or_kind(&seg.cant_mm, &seg.kind);
                sink.invalid(
                    &span,
                    "cant_mm",
                    format!(
                        "segment {}: the cant steps by {:.1} mm where it starts (a step rolls the track, and every vehicle body on it, at once); put a transition (clothoid, bloss or cosine) before it",
                        i + 1,
                        (after - before).abs() * 1e3
                    ),
                );
            }
        }
        // Vertical curves must fit: each rounding takes at most half of either segment.
        if let Some(rv) = vertical_radius {
            for i in 1..n {
                let dg = inputs[i].gradient - inputs[i - 1].gradient;
                let half = 0.5 * rv * dg.abs();
                if half > 0.5 * inputs[i].length.min(inputs[i - 1].length) {
                    let seg = spec.segment[i].get_ref();
                    let span = key_or_kind(&seg.gradient_permille, &seg.kind);
                    sink.invalid(
                        &span,
                        "gradient_permille",
                        format!(
                            "segment {}: gradient_permille = {}: the vertical curve (R = {rv} m, {:.1} ‰ change) is {:.1} m long and does not fit into half of this segment or the previous one; use a smaller vertical_curve_radius_m or longer segments",
                            i + 1,
                            inputs[i].gradient * 1e3,
                            dg * 1e3,
                            2.0 * half
                        ),
                    );
                }
            }
        }
        let cant_base = cant_base_mm * 1e-3;
        let alignment_ok = sink.errors.is_empty();
        let alignment = if alignment_ok && !inputs.is_empty() {
            Some(Alignment::build(&inputs, cant_base, vertical_radius))
        } else {
            None
        };
        let track_length: f64 = inputs.iter().map(|s| s.length).sum();

        // Irregularities.
        let mut irregularities = None;
        let mut irregularity_file = None;
        if let Some(irr) = &spec.irregularities {
            irregularities = check_irregularities(&mut sink, irr, &dir, track_length);
            if let (Some(_), Some(file)) = (&irregularities, &irr.get_ref().file) {
                irregularity_file = Some(dir.join(file.get_ref()));
            }
        }

        let rail_sections = check_rail_sections(
            &mut sink,
            spec,
            &dir,
            RailSection {
                start: 0.0,
                profiles,
                inclination: incl.unwrap_or(0.0),
                gauge: gauge_mm * 1e-3,
                friction: None,
                transition: 0.0,
            },
            track_length,
        );

        let rail_support = spec
            .rail_support
            .as_ref()
            .map(|r| check_rail_support(&mut sink, r.get_ref()));

        let name = spec
            .name
            .as_ref()
            .map_or_else(|| source_name.to_owned(), |n| n.get_ref().clone());
        sink.finish()?;
        let alignment = alignment.ok_or_else(|| TrackErrors { errors: Vec::new() })?;
        Ok(TrackModel {
            name,
            source: source_name.to_owned(),
            gauge: gauge_mm * 1e-3,
            rail_sections,
            alignment,
            irregularities,
            irregularity_file,
            rail_support,
        })
    }

    /// The track frame at s \[m\]: position, heading, curvature, cant, gradient and their
    /// d/ds. O(log n_segments), no allocation. Beyond either end the track continues with the
    /// end's curvature, cant and gradient.
    #[inline]
    pub fn frame_at(&self, s: f64) -> TrackFrame {
        self.alignment.frame_at(s)
    }

    /// The irregularity at s \[m\] with its d/ds; zero on ideal track (nothing is evaluated)
    /// and outside the irregularity series.
    #[inline]
    pub fn irregularity_at(&self, s: f64) -> Irregularity {
        match &self.irregularities {
            Some(series) => series.at(s),
            None => Irregularity::default(),
        }
    }

    /// Name (the file's `name`, or its path).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The file the track was read from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// \[m\] total length of the alignment.
    pub fn length(&self) -> f64 {
        self.alignment.length
    }

    /// \[m\] nominal gauge at the track's start (`gauge_mm`; a rail section may change it,
    /// [`RailSection::gauge`]).
    pub fn gauge(&self) -> f64 {
        self.gauge
    }

    /// \[m\] cant base (distance between rail-head centres).
    pub fn cant_base(&self) -> f64 {
        self.alignment.cant_base
    }

    /// \[rad\] rail inclination (atan(1/40) for 1:40), toward the track centre, from s = 0 to the
    /// first rail section (the whole track without sections).
    pub fn rail_inclination(&self) -> f64 {
        self.rail_sections[0].inclination
    }

    /// Rail profile of the left (`[0]`) and right (`[1]`) rail from s = 0 to the first rail
    /// section (the whole track without sections).
    pub fn rail_profiles(&self) -> &[RailProfile; 2] {
        &self.rail_sections[0].profiles
    }

    /// The rails along the track: the first from s = 0, each of the others from its start to
    /// the next one's (the last to the end and beyond).
    pub fn rail_sections(&self) -> &[RailSection] {
        &self.rail_sections
    }

    /// The index of the rail section at s \[m\] (0 before the track's start): the last that
    /// begins at or before s.
    #[inline]
    pub fn rail_section_at(&self, s: f64) -> usize {
        // (few sections: a linear scan from the end)
        self.rail_sections
            .iter()
            .rposition(|r| r.start <= s)
            .unwrap_or(0)
    }

    /// The rails at s \[m\]: the section of [`rail_section_at`](Self::rail_section_at), with
    /// weight (s − start)/transition inside its transition (the section before the rest), else 1.
    #[inline]
    pub fn rail_blend_at(&self, s: f64) -> RailBlend {
        let section = self.rail_section_at(s);
        let r = &self.rail_sections[section];
        // (the first section has no transition, and before the track's start s - start < 0)
        let along = s - r.start;
        let weight = if section > 0 && along < r.transition {
            along / r.transition
        } else {
            1.0
        };
        RailBlend { section, weight }
    }

    /// The compiled segments.
    pub fn segments(&self) -> &[Segment] {
        &self.alignment.segments
    }

    /// The irregularity series, `None` on ideal track.
    pub fn irregularities(&self) -> Option<&IrregularitySeries> {
        self.irregularities.as_ref()
    }

    /// The data files the track read besides its own: rail profile files of every section, then
    /// the CSV of measured irregularities; each once, in that order (a log records them, so that
    /// a re-run can tell when one has changed).
    pub fn data_files(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = Vec::new();
        let profiles = self.rail_sections.iter().flat_map(|r| &r.profiles);
        let paths = profiles.filter_map(|p| match p {
            RailProfile::File(path) => Some(path.as_path()),
            RailProfile::Uic60 => None,
        });
        for path in paths.chain(self.irregularity_file.as_deref()) {
            if !files.contains(&path) {
                files.push(path);
            }
        }
        files
    }

    /// The elastic rail support, `None` for rigid rails.
    pub fn rail_support(&self) -> Option<&RailSupport> {
        self.rail_support.as_ref()
    }
}

/// The rails of a stretch of track: both rails' profiles and their inclination.
#[derive(Debug, Clone, PartialEq)]
pub struct RailSection {
    /// \[m\] track position where the section begins (0 for the first).
    pub start: f64,
    /// Rail profile of the left (`[0]`) and right (`[1]`) rail.
    pub profiles: [RailProfile; 2],
    /// \[rad\] rail inclination toward the track centre.
    pub inclination: f64,
    /// \[m\] nominal gauge (the first section's is the track's `gauge_mm`); the gauge
    /// irregularity adds to it.
    pub gauge: f64,
    /// Wheel/rail friction on this section (checked); `None`: the scene's.
    pub friction: Option<railsim_spec::FrictionSpec>,
    /// \[m\] from `start` over this length a wheel's contact forces pass linearly from the
    /// section before's rails to these ([`TrackModel::rail_blend_at`]); 0: at once.
    pub transition: f64,
}

/// The rails under a point of the track ([`TrackModel::rail_blend_at`]): a section and its
/// weight; in a transition the section before carries the rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailBlend {
    /// Index into [`TrackModel::rail_sections`].
    pub section: usize,
    /// \[-\] its weight, in [0, 1]; below 1 (in its transition) section − 1 weighs 1 − weight.
    pub weight: f64,
}

/// \[mm\] Most a rail section's gauge may differ from the track's `gauge_mm`: a section gauge
/// further off is taken for a slip of the pen (a gauge in metres, another track's gauge) rather
/// than a widening.
const SECTION_GAUGE_RANGE_MM: f64 = 50.0;

/// Check a `gauge_mm` value (`prefix` names where it is); with `track` (the track's gauge, mm)
/// also that it lies within [`SECTION_GAUGE_RANGE_MM`] of it. `None` (reported) if bad.
fn check_gauge(sink: &mut Sink, v: &Spanned<f64>, prefix: &str, track: Option<f64>) -> Option<f64> {
    let g = *v.get_ref();
    if !(g.is_finite() && (600.0..=2000.0).contains(&g)) {
        sink.invalid(
            &span_of(v),
            "gauge_mm",
            format!(
                "{prefix}gauge_mm = {} must be between 600 and 2000 (a plausible track gauge in mm)",
                short_number(g)
            ),
        );
        return None;
    }
    if let Some(t) = track
        && (g - t).abs() > SECTION_GAUGE_RANGE_MM
    {
        sink.invalid(
            &span_of(v),
            "gauge_mm",
            format!(
                "{prefix}gauge_mm = {} must lie within {} mm of the track's gauge_mm = {}",
                short_number(g),
                short_number(SECTION_GAUGE_RANGE_MM),
                short_number(t)
            ),
        );
        return None;
    }
    Some(g)
}

/// Parse a `rail_inclination` value (`prefix` names where it is, e.g. `rail_section 2: `);
/// `None` (reported) if bad.
fn check_inclination(sink: &mut Sink, v: &Spanned<String>, prefix: &str) -> Option<f64> {
    let incl = parse_inclination(v.get_ref());
    if incl.is_none() {
        sink.invalid(
            &span_of(v),
            "rail_inclination",
            format!(
                "{prefix}rail_inclination = {:?} must be \"1:N\" with 5 ≤ N ≤ 1000 (e.g. \"1:40\") or \"none\"",
                v.get_ref()
            ),
        );
    }
    incl
}

/// Resolve a `rail_profile` table (`prefix` names where it is, e.g. `rail_section 2: `): a
/// built-in name or a file relative to the track file; bad names are reported (and read as
/// UIC60 so that checking goes on).
fn check_rail_profiles(
    sink: &mut Sink,
    rp: &Spanned<RailProfileSpec>,
    dir: &Path,
    prefix: &str,
) -> [RailProfile; 2] {
    let mut profiles = [RailProfile::Uic60, RailProfile::Uic60];
    let rp = rp.get_ref();
    for (i, (side, v)) in [("left", &rp.left), ("right", &rp.right)]
        .into_iter()
        .enumerate()
    {
        let name = v.get_ref().trim();
        let lower = name.to_ascii_lowercase();
        if lower == "uic60" {
            profiles[i] = RailProfile::Uic60;
        } else if name.contains('/') || name.contains('\\') || name.contains('.') {
            let path = dir.join(name);
            if path.is_file() {
                profiles[i] = RailProfile::File(path);
            } else {
                sink.invalid(
                    &span_of(v),
                    &format!("rail_profile.{side}"),
                    format!(
                        "{prefix}rail_profile.{side} = {name:?}: file {} not found (paths are relative to the track file)",
                        path.display()
                    ),
                );
            }
        } else {
            sink.invalid(
                &span_of(v),
                &format!("rail_profile.{side}"),
                format!(
                    "{prefix}rail_profile.{side} = {name:?} is not a built-in profile (expected one of {:?} or a file path)",
                    BUILTIN_RAIL_PROFILES
                ),
            );
        }
    }
    profiles
}

/// The rail sections: `first` from s = 0, then each `[[rail_section]]`, whose start must lie
/// inside the track (0 < start < `length`) and after the one before, and whose keys left out
/// keep the section before's values.
fn check_rail_sections(
    sink: &mut Sink,
    spec: &TrackSpec,
    dir: &Path,
    first: RailSection,
    length: f64,
) -> Vec<RailSection> {
    let first_gauge = first.gauge * 1e3;
    let mut out = vec![first];
    for (i, sec) in spec.rail_section.iter().enumerate() {
        let sec = sec.get_ref();
        let prev = out[out.len() - 1].clone();
        let start = *sec.start_m.get_ref();
        let what = format!("rail_section {}: ", i + 1);
        if !(start.is_finite() && start > prev.start && start < length) {
            sink.invalid(
                &span_of(&sec.start_m),
                "start_m",
                format!(
                    "{what}start_m = {} must lie after the previous section's start ({} m) and before the track's end ({} m)",
                    short_number(start),
                    short_number(prev.start),
                    short_number(length)
                ),
            );
            continue;
        }
        if sec.rail_profile.is_none()
            && sec.rail_inclination.is_none()
            && sec.gauge_mm.is_none()
            && sec.friction.is_none()
        {
            sink.invalid(
                &span_of(&sec.start_m),
                "rail_section",
                format!(
                    "{what}changes nothing: give one or more of rail_profile = {{ left = ..., right = ... }}, rail_inclination, gauge_mm and friction"
                ),
            );
        }
        let profiles = sec.rail_profile.as_ref().map_or(prev.profiles, |rp| {
            check_rail_profiles(sink, rp, dir, &what)
        });
        let inclination = sec.rail_inclination.as_ref().map_or(prev.inclination, |v| {
            check_inclination(sink, v, &what).unwrap_or(prev.inclination)
        });
        let gauge = sec.gauge_mm.as_ref().map_or(prev.gauge, |v| {
            check_gauge(sink, v, &what, Some(first_gauge)).map_or(prev.gauge, |g| g * 1e-3)
        });
        let friction = match &sec.friction {
            None => prev.friction.clone(),
            Some(f) => match f.get_ref().problem("friction") {
                Some(message) => {
                    sink.invalid(&span_of(f), "friction", format!("{what}{message}"));
                    prev.friction.clone()
                }
                None => Some(f.get_ref().clone()),
            },
        };
        let transition = match &sec.transition_m {
            None => 0.0,
            Some(v) => {
                let l = *v.get_ref();
                if !(l.is_finite() && l >= 0.0 && start + l <= length) {
                    sink.invalid(
                        &span_of(v),
                        "transition_m",
                        format!(
                            "{what}transition_m = {} must be at least 0 and end on the track (start_m + transition_m ≤ {} m)",
                            short_number(l),
                            short_number(length)
                        ),
                    );
                    0.0
                } else {
                    l
                }
            }
        };
        // (a transition ends before the next section begins: checked against the next one)
        if let Some(last) = out.last()
            && out.len() > 1
            && last.start + last.transition > start
        {
            sink.invalid(
                &span_of(&sec.start_m),
                "start_m",
                format!(
                    "{what}start_m = {} lies inside the transition of the section before (to {} m)",
                    short_number(start),
                    short_number(last.start + last.transition)
                ),
            );
        }
        out.push(RailSection {
            start,
            profiles,
            inclination,
            gauge,
            friction,
            transition,
        });
    }
    out
}

/// Check the `[rail_support]` table and convert it to SI (each value is reported on its own).
fn check_rail_support(sink: &mut Sink, r: &crate::spec::RailSupportSpec) -> RailSupport {
    let mut get = |v: &Spanned<f64>, key: &str, lo: f64, hi: f64, unit: f64, what: &str| {
        let x = *v.get_ref();
        if !(x.is_finite() && (lo..=hi).contains(&x)) {
            sink.invalid(
                &span_of(v),
                &format!("rail_support.{key}"),
                format!(
                    "rail_support.{key} = {} must be between {} and {} ({what})",
                    short_number(x),
                    short_number(lo),
                    short_number(hi)
                ),
            );
        }
        x * unit
    };
    RailSupport {
        mass: get(
            &r.mass_kg,
            "mass_kg",
            1.0,
            10_000.0,
            1.0,
            "kg of rail per wheel",
        ),
        lateral_stiffness: get(
            &r.lateral_stiffness_mn_m,
            "lateral_stiffness_mn_m",
            1.0,
            10_000.0,
            1e6,
            "MN/m per wheel",
        ),
        lateral_damping: get(
            &r.lateral_damping_kns_m,
            "lateral_damping_kns_m",
            0.0,
            100_000.0,
            1e3,
            "kN s/m per wheel",
        ),
        vertical_stiffness: get(
            &r.vertical_stiffness_mn_m,
            "vertical_stiffness_mn_m",
            1.0,
            10_000.0,
            1e6,
            "MN/m per wheel",
        ),
        vertical_damping: get(
            &r.vertical_damping_kns_m,
            "vertical_damping_kns_m",
            0.0,
            100_000.0,
            1e3,
            "kN s/m per wheel",
        ),
    }
}

/// Check one segment and convert it; the returned input is a placeholder when invalid.
fn check_segment(
    sink: &mut Sink<'_>,
    index: usize,
    seg: &Spanned<SegmentSpec>,
    min_radius: f64,
) -> SegmentInput {
    let s = seg.get_ref();
    let kind_name = s.kind.get_ref().as_str();
    let kind = match kind_name {
        "tangent" => Some(SegmentKind::Tangent),
        "curve" => Some(SegmentKind::Curve),
        other => match TransitionShape::ALL.into_iter().find(|t| t.name() == other) {
            Some(shape) => Some(SegmentKind::Transition(shape)),
            None => {
                sink.invalid(
                    &span_of(&s.kind),
                    "type",
                    format!(
                        "segment {index}: type = {other:?} must be \"tangent\", \"curve\" or a transition (\"clothoid\", \"bloss\" or \"cosine\")"
                    ),
                );
                None
            }
        },
    };
    let label = format!("segment {index} ({kind_name})");
    let mut out = SegmentInput {
        kind: kind.unwrap_or(SegmentKind::Tangent),
        length: 1.0,
        curvature: (0.0, 0.0),
        cant: (0.0, 0.0),
        gradient: 0.0,
    };
    let seg_span = seg.span();
    match &s.length_m {
        None => sink.invalid(
            &seg_span,
            "length_m",
            format!("{label}: missing key length_m (length in m, > 0)"),
        ),
        Some(v) => {
            let l = *v.get_ref();
            let max = match kind {
                Some(SegmentKind::Transition(_)) => MAX_TRANSITION_LENGTH_M,
                _ => MAX_SEGMENT_LENGTH_M,
            };
            if !(l.is_finite() && l > 0.0) {
                sink.invalid(
                    &span_of(v),
                    "length_m",
                    format!("{label}: length_m = {l} must be positive"),
                );
            } else if l > max {
                sink.invalid(
                    &span_of(v),
                    "length_m",
                    format!(
                        "{label}: length_m = {} is longer than the {} m accepted for this segment type",
                        short_number(l),
                        short_number(max)
                    ),
                );
            } else {
                out.length = l;
            }
        }
    }
    if let Some(v) = &s.gradient_permille {
        let g = *v.get_ref();
        if !(g.is_finite() && g.abs() <= MAX_GRADIENT_PERMILLE) {
            sink.invalid(
                &span_of(v),
                "gradient_permille",
                format!(
                    "{label}: gradient_permille = {} must be between -{MAX_GRADIENT_PERMILLE} and {MAX_GRADIENT_PERMILLE}",
                    short_number(g)
                ),
            );
        } else {
            out.gradient = g * 1e-3;
        }
    }
    let Some(kind) = kind else { return out };
    if kind != SegmentKind::Curve {
        let why = if let SegmentKind::Transition(_) = kind {
            "a transition takes curvature and cant from its neighbours"
        } else {
            "a tangent is straight with no cant"
        };
        for (key, present) in [
            ("radius_m", s.radius_m.as_ref().map(span_of)),
            ("cant_mm", s.cant_mm.as_ref().map(span_of)),
            ("direction", s.direction.as_ref().map(span_of)),
        ] {
            if let Some(span) = present {
                sink.invalid(
                    &span,
                    key,
                    format!("{label}: key {key} is not allowed ({why})"),
                );
            }
        }
        return out;
    }
    // Curve.
    let mut radius = None;
    match &s.radius_m {
        None => sink.invalid(
            &seg_span,
            "radius_m",
            format!("{label}: missing key radius_m (curve radius in m)"),
        ),
        Some(v) => {
            let r = *v.get_ref();
            if !r.is_finite() || r <= 0.0 {
                sink.invalid(
                    &span_of(v),
                    "radius_m",
                    format!("{label}: radius_m = {r} must be positive"),
                );
            } else if r < min_radius {
                sink.invalid(
                    &span_of(v),
                    "radius_m",
                    format!(
                        "{label}: radius_m = {} is tighter than the minimum radius {min_radius} m",
                        short_number(r)
                    ),
                );
            } else {
                radius = Some(r);
            }
        }
    }
    let mut sign = None;
    match &s.direction {
        None => sink.invalid(
            &seg_span,
            "direction",
            format!("{label}: missing key direction (\"left\" or \"right\")"),
        ),
        Some(v) => match v.get_ref().as_str() {
            "left" => sign = Some(1.0),
            "right" => sign = Some(-1.0),
            other => sink.invalid(
                &span_of(v),
                "direction",
                format!("{label}: direction = {other:?} must be \"left\" or \"right\""),
            ),
        },
    }
    let mut cant_mm = 0.0;
    if let Some(v) = &s.cant_mm {
        let c = *v.get_ref();
        if !(c.is_finite() && c.abs() <= MAX_CANT_MM) {
            sink.invalid(
                &span_of(v),
                "cant_mm",
                format!(
                    "{label}: cant_mm = {} must be between -{MAX_CANT_MM} and {MAX_CANT_MM}",
                    short_number(c)
                ),
            );
        } else {
            cant_mm = c;
        }
    }
    if let (Some(r), Some(sg)) = (radius, sign) {
        out.curvature = (sg / r, sg / r);
        // Left curve banked toward its centre: the right rail is higher (cant < 0).
        let c = -sg * cant_mm * 1e-3;
        out.cant = (c, c);
    }
    out.kind = kind;
    out
}

/// Check the `[irregularities]` table and build the series.
fn check_irregularities(
    sink: &mut Sink<'_>,
    irr: &Spanned<IrregularitySpec>,
    dir: &Path,
    track_length: f64,
) -> Option<IrregularitySeries> {
    let p = irr.get_ref();
    let span = irr.span();
    let kind = p.kind.get_ref().as_str();
    let used: &[&str] = match kind {
        "none" => &[],
        "measured" => &["file", "taper_m"],
        "synthetic" => &[
            "spectrum",
            "seed",
            "wavelength_min_m",
            "wavelength_max_m",
            "step_m",
            "components",
            "taper_m",
            "start_m",
            "length_m",
        ],
        other => {
            sink.invalid(
                &span_of(&p.kind),
                "type",
                format!(
                    "irregularities: type = {other:?} must be \"none\", \"measured\" or \"synthetic\""
                ),
            );
            return None;
        }
    };
    let present: [(&str, Option<Range<usize>>); 10] = [
        ("file", p.file.as_ref().map(span_of)),
        ("spectrum", p.spectrum.as_ref().map(span_of)),
        ("seed", p.seed.as_ref().map(span_of)),
        ("wavelength_min_m", p.wavelength_min_m.as_ref().map(span_of)),
        ("wavelength_max_m", p.wavelength_max_m.as_ref().map(span_of)),
        ("step_m", p.step_m.as_ref().map(span_of)),
        ("components", p.components.as_ref().map(span_of)),
        ("taper_m", p.taper_m.as_ref().map(span_of)),
        ("start_m", p.start_m.as_ref().map(span_of)),
        ("length_m", p.length_m.as_ref().map(span_of)),
    ];
    for (key, sp) in present {
        if let Some(sp) = sp
            && !used.contains(&key)
        {
            sink.invalid(
                &sp,
                key,
                format!("irregularities: key {key} is not used by type = {kind:?}"),
            );
        }
    }
    match kind {
        "measured" => {
            let Some(file) = &p.file else {
                sink.invalid(
                    &span,
                    "file",
                    "irregularities: missing key file (CSV path relative to the track file)"
                        .to_owned(),
                );
                return None;
            };
            let path = dir.join(file.get_ref());
            let display = path.display().to_string();
            if !path.is_file() {
                sink.invalid(
                    &span_of(file),
                    "file",
                    format!(
                        "irregularities: file = {:?}: {display} not found",
                        file.get_ref()
                    ),
                );
                return None;
            }
            let series = match irregularity::read_csv(&path, &display) {
                Ok(series) => series,
                Err(e) => {
                    sink.errors.extend(e.errors);
                    return None;
                }
            };
            let at = series.positions();
            let (s0, s1) = (at[0], at[at.len() - 1]);
            if let Some(v) = &p.taper_m {
                let t = *v.get_ref();
                let max = (s1 - s0) / 2.0;
                if !(t.is_finite() && t >= 0.0 && t <= max) {
                    sink.invalid(
                        &span_of(v),
                        "taper_m",
                        format!("irregularities: taper_m = {} must be between 0 and half the length of the data in {display} ({} m)", short_number(t), short_number(max)),
                    );
                    return None;
                }
                return Some(series.tapered(t));
            }
            // Outside its range the irregularity is zero: data that do not end there would meet
            // the vehicle as a step.
            if let Some((c, k)) = series.end_beyond_mm(irregularity::CSV_END_MAX_MM) {
                let v = series.channel(c)[k] * 1e3;
                sink.invalid(
                    &span_of(file),
                    "file",
                    format!(
                        "irregularities: {display}: {} = {} at distance_m = {} (its {} row): outside its range the irregularity is zero, so a vehicle would meet a {} mm step there; expected the data to start and end within {} mm of zero, or set taper_m to fade them in and out",
                        irregularity::CSV_COLUMNS[1 + c as usize],
                        short_number(v),
                        short_number(at[k]),
                        if k == 0 { "first" } else { "last" },
                        short_number(v.abs()),
                        irregularity::CSV_END_MAX_MM
                    ),
                );
                return None;
            }
            Some(series)
        }
        "synthetic" => {
            let mut ok = true;
            let mut require = |sink: &mut Sink<'_>, key: &str, what: &str, v: bool| {
                if !v {
                    sink.invalid(
                        &span,
                        key,
                        format!("irregularities: missing key {key} ({what})"),
                    );
                    ok = false;
                }
            };
            require(
                sink,
                "spectrum",
                "\"erri_b176_low\" or \"erri_b176_high\"",
                p.spectrum.is_some(),
            );
            require(sink, "seed", "a non-negative integer", p.seed.is_some());
            require(
                sink,
                "wavelength_min_m",
                "shortest wavelength in m",
                p.wavelength_min_m.is_some(),
            );
            require(
                sink,
                "wavelength_max_m",
                "longest wavelength in m",
                p.wavelength_max_m.is_some(),
            );
            let spectrum = p.spectrum.as_ref().and_then(|v| {
                let sp = Spectrum::from_name(v.get_ref());
                if sp.is_none() {
                    sink.invalid(
                        &span_of(v),
                        "spectrum",
                        format!(
                            "irregularities: spectrum = {:?} must be one of {:?}",
                            v.get_ref(),
                            Spectrum::NAMES
                        ),
                    );
                }
                sp
            });
            let positive = |sink: &mut Sink<'_>, key: &str, v: &Option<Spanned<f64>>| {
                v.as_ref().and_then(|v| {
                    let x = *v.get_ref();
                    if x.is_finite() && x > 0.0 {
                        Some(x)
                    } else {
                        sink.invalid(
                            &span_of(v),
                            key,
                            format!("irregularities: {key} = {x} must be positive"),
                        );
                        None
                    }
                })
            };
            let lmin = positive(sink, "wavelength_min_m", &p.wavelength_min_m);
            let lmax = positive(sink, "wavelength_max_m", &p.wavelength_max_m);
            if let (Some(a), Some(b), Some(v)) = (lmin, lmax, &p.wavelength_max_m)
                && b <= a
            {
                sink.invalid(
                    &span_of(v),
                    "wavelength_max_m",
                    format!("irregularities: wavelength_max_m = {b} must be greater than wavelength_min_m = {a}"),
                );
                ok = false;
            }
            let start = match &p.start_m {
                Some(v) if !(v.get_ref().is_finite() && *v.get_ref() >= 0.0) => {
                    sink.invalid(
                        &span_of(v),
                        "start_m",
                        format!("irregularities: start_m = {} must be ≥ 0", v.get_ref()),
                    );
                    ok = false;
                    0.0
                }
                Some(v) => *v.get_ref(),
                None => 0.0,
            };
            let length = match &p.length_m {
                Some(_) => positive(sink, "length_m", &p.length_m),
                None if track_length - start > 0.0 => Some(track_length - start),
                None => {
                    sink.invalid(
                        &span,
                        "length_m",
                        "irregularities: start_m leaves no track to cover; set length_m".to_owned(),
                    );
                    None
                }
            };
            let step = match &p.step_m {
                Some(_) => positive(sink, "step_m", &p.step_m),
                None => lmin.map(|a| a / 8.0),
            };
            if let (Some(st), Some(a), Some(v)) = (step, lmin, &p.step_m)
                && st > a / 4.0
            {
                sink.invalid(
                    &span_of(v),
                    "step_m",
                    format!(
                        "irregularities: step_m = {} must be at most wavelength_min_m / 4 = {}",
                        short_number(st),
                        short_number(a / 4.0)
                    ),
                );
                ok = false;
            }
            let taper = match &p.taper_m {
                Some(v) => {
                    let t = *v.get_ref();
                    let max = length.unwrap_or(f64::INFINITY) / 2.0;
                    if !(t.is_finite() && t >= 0.0 && t <= max) {
                        sink.invalid(
                            &span_of(v),
                            "taper_m",
                            format!("irregularities: taper_m = {} must be between 0 and half the series length ({max} m)", short_number(t)),
                        );
                        ok = false;
                    }
                    t
                }
                // a fade over the longest wavelength (within half the series) by default, so
                // that the series does not start and end with a step
                None => match (lmax, length) {
                    (Some(b), Some(l)) => b.min(l / 2.0),
                    _ => 0.0,
                },
            };
            let components = match (&p.components, lmin, lmax, length) {
                (Some(v), ..) => {
                    let c = *v.get_ref();
                    if !(1..=1_000_000).contains(&c) {
                        sink.invalid(
                            &span_of(v),
                            "components",
                            format!(
                                "irregularities: components = {c} must be between 1 and 1000000"
                            ),
                        );
                        ok = false;
                    }
                    Some(c as usize)
                }
                (None, Some(a), Some(b), Some(l)) if b > a => Some(default_components(a, b, l)),
                _ => None,
            };
            let (
                Some(spectrum),
                Some(seed),
                Some(lmin),
                Some(lmax),
                Some(step),
                Some(length),
                Some(components),
                true,
            ) = (
                spectrum,
                p.seed.as_ref().map(|v| *v.get_ref()),
                lmin,
                lmax,
                step,
                length,
                components,
                ok,
            )
            else {
                return None;
            };
            let samples = length / step;
            if samples * components as f64 > 4e10 {
                sink.invalid(
                    &span,
                    "components",
                    format!("irregularities: {} samples × {} components is too much work; use fewer components, a larger step_m or a shorter length_m", short_number(samples.round()), short_number(components as f64)),
                );
                return None;
            }
            if !sink.errors.is_empty() {
                return None;
            }
            Some(irregularity::synthesize(&SyntheticParams {
                spectrum,
                seed,
                wavelength_min: lmin,
                wavelength_max: lmax,
                step,
                components,
                taper,
                start,
                length,
            }))
        }
        _ => None,
    }
}
