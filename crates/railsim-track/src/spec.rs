//! `TrackSpec`: the track file as written, one to one with the TOML, in the file's units.
//!
//! Every field keeps its span so that [`crate::TrackModel::compile`] can report
//! `file:line:col`. Unknown keys are rejected (`deny_unknown_fields`). The format is documented
//! in `docs/formats/track.md`.
//!
//! [`TrackSpec::from_toml_str`] reads the root table, every `[[segment]]` and the
//! `[irregularities]` table separately, so that a structural problem (unknown key, missing key,
//! wrong type) in each of them is reported in the same run; within one table serde stops at the
//! first structural problem. Range problems are all reported by the compile step.

use serde::Deserialize;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

use crate::error::{SourceMap, TrackErrors};

/// A whole track file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    /// Free-text name of the track.
    #[serde(default)]
    pub name: Option<Spanned<String>>,
    /// \[mm\] nominal track gauge (1435 for standard gauge).
    pub gauge_mm: Spanned<f64>,
    /// Rail inclination as `"1:N"` (e.g. `"1:40"`), or `"none"` for vertical rails.
    pub rail_inclination: Spanned<String>,
    /// Rail profile of each rail.
    pub rail_profile: Spanned<RailProfileSpec>,
    /// \[mm\] distance between the rail-head centres on which cant is measured; default
    /// `gauge_mm + 65` (1500 for standard gauge).
    #[serde(default)]
    pub cant_base_mm: Option<Spanned<f64>>,
    /// \[m\] smallest curve radius accepted for this track; default 50 m (the hard limit).
    #[serde(default)]
    pub min_radius_m: Option<Spanned<f64>>,
    /// \[m\] radius of the parabolic vertical curves that round every change of gradient; when
    /// absent the gradient changes abruptly at segment joins.
    #[serde(default)]
    pub vertical_curve_radius_m: Option<Spanned<f64>>,
    /// The alignment: segments in the direction of travel, starting at s = 0.
    #[serde(default)]
    pub segment: Vec<Spanned<SegmentSpec>>,
    /// Track irregularities; none when absent.
    #[serde(default)]
    pub irregularities: Option<Spanned<IrregularitySpec>>,
    /// Elastic rail support (a moving rail mass under each wheel); rigid rails when absent.
    #[serde(default)]
    pub rail_support: Option<Spanned<RailSupportSpec>>,
    /// Sections with other rails, in track order: from `start_m` on (to the next section or
    /// the end) the rails have the section's profiles, inclination, gauge and friction; the
    /// top-level values hold from s = 0 to the first section.
    #[serde(default)]
    pub rail_section: Vec<Spanned<RailSectionSpec>>,
    /// Line index of the text this spec was read from (empty when built in code).
    #[serde(skip)]
    pub source: SourceMap,
}

/// Rail profile per side: a built-in name (`"uic60"`) or a file path relative to the track file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RailProfileSpec {
    /// Profile of the left rail.
    pub left: Spanned<String>,
    /// Profile of the right rail.
    pub right: Spanned<String>,
}

/// A `[[rail_section]]`: where other rails begin, and what they are (a key left out keeps the
/// value of the section before).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RailSectionSpec {
    /// \[m\] track position where the section begins.
    pub start_m: Spanned<f64>,
    /// Rail profile per side from here on.
    #[serde(default)]
    pub rail_profile: Option<Spanned<RailProfileSpec>>,
    /// Rail inclination from here on, `"1:N"` or `"none"`.
    #[serde(default)]
    pub rail_inclination: Option<Spanned<String>>,
    /// \[mm\] track gauge from here on (e.g. widened in a tight curve).
    #[serde(default)]
    pub gauge_mm: Option<Spanned<f64>>,
    /// Wheel/rail friction from here on, instead of the scene's (a lubricated curve, a wet or
    /// leaf-covered stretch): a number or coefficients by contact angle.
    #[serde(default)]
    pub friction: Option<Spanned<railsim_spec::FrictionSpec>>,
    /// \[m\] length over which the rails change from the section before's to these (from
    /// `start_m` on); 0 (the default): at once.
    #[serde(default)]
    pub transition_m: Option<Spanned<f64>>,
}

/// The `[rail_support]` table: under each wheel a rail mass that moves with the wheelset, held
/// laterally and vertically by a spring and a damper in parallel (`docs/models/track.md`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RailSupportSpec {
    /// \[kg\] rail mass moving with each wheel.
    pub mass_kg: Spanned<f64>,
    /// \[MN/m\] lateral stiffness of the rail's support, per wheel.
    pub lateral_stiffness_mn_m: Spanned<f64>,
    /// \[kN s/m\] lateral damping of the rail's support, per wheel.
    pub lateral_damping_kns_m: Spanned<f64>,
    /// \[MN/m\] vertical stiffness of the rail's support, per wheel.
    pub vertical_stiffness_mn_m: Spanned<f64>,
    /// \[kN s/m\] vertical damping of the rail's support, per wheel.
    pub vertical_damping_kns_m: Spanned<f64>,
}

/// One alignment segment. Which keys are required depends on `type`:
/// `tangent` and the transitions take `length_m` (and `gradient_permille`); `curve` also takes
/// `radius_m`, `direction` and `cant_mm`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// `"tangent"`, `"clothoid"`, `"bloss"`, `"cosine"` (transitions) or `"curve"`.
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    /// \[m\] length along the track (plan projection).
    #[serde(default)]
    pub length_m: Option<Spanned<f64>>,
    /// \[m\] radius of a `curve`.
    #[serde(default)]
    pub radius_m: Option<Spanned<f64>>,
    /// \[mm\] cant (superelevation) of a `curve`, positive when the outer rail is higher;
    /// default 0.
    #[serde(default)]
    pub cant_mm: Option<Spanned<f64>>,
    /// `"left"` or `"right"`: the side the centre of a `curve` lies on, seen in the direction of
    /// travel.
    #[serde(default)]
    pub direction: Option<Spanned<String>>,
    /// \[‰\] gradient, positive uphill in the direction of travel; default 0.
    #[serde(default)]
    pub gradient_permille: Option<Spanned<f64>>,
}

/// The `[irregularities]` table. Keys used depend on `type`:
/// `none`; `measured` (`file`, optional `taper_m`); `synthetic` (`spectrum`, `seed`, `wavelength_min_m`,
/// `wavelength_max_m`, optional `step_m`, `components`, `taper_m`, `start_m`, `length_m`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrregularitySpec {
    /// `"none"`, `"measured"` or `"synthetic"`.
    #[serde(rename = "type")]
    pub kind: Spanned<String>,
    /// CSV file of a `measured` irregularity, relative to the track file.
    #[serde(default)]
    pub file: Option<Spanned<String>>,
    /// Spectrum of a `synthetic` irregularity: `"erri_b176_low"` or `"erri_b176_high"`.
    #[serde(default)]
    pub spectrum: Option<Spanned<String>>,
    /// Seed of the random phases (same seed, same series).
    #[serde(default)]
    pub seed: Option<Spanned<u64>>,
    /// \[m\] shortest wavelength generated.
    #[serde(default)]
    pub wavelength_min_m: Option<Spanned<f64>>,
    /// \[m\] longest wavelength generated.
    #[serde(default)]
    pub wavelength_max_m: Option<Spanned<f64>>,
    /// \[m\] sampling step of the generated series; default `wavelength_min_m / 8`.
    #[serde(default)]
    pub step_m: Option<Spanned<f64>>,
    /// \[-\] number of cosines per channel; default enough for a frequency spacing of
    /// 2π / (2 · length).
    #[serde(default)]
    pub components: Option<Spanned<u64>>,
    /// \[m\] length of the raised-cosine fade-in and fade-out at both ends; synthetic: default
    /// `wavelength_max_m` (at most half the series); measured: default none.
    #[serde(default)]
    pub taper_m: Option<Spanned<f64>>,
    /// \[m\] where the generated series starts; default 0.
    #[serde(default)]
    pub start_m: Option<Spanned<f64>>,
    /// \[m\] length of the generated series; default the rest of the track.
    #[serde(default)]
    pub length_m: Option<Spanned<f64>>,
}

impl TrackSpec {
    /// Read a track from TOML text. `source_name` (usually the path) prefixes every message.
    ///
    /// Structural problems of the root table, of every `[[segment]]` and of
    /// `[irregularities]` are all reported together.
    pub fn from_toml_str(text: &str, source_name: &str) -> Result<TrackSpec, TrackErrors> {
        let map = SourceMap::new(text);
        let mut sink = crate::error::Sink::new(source_name, &map);
        let root = match DeTable::parse(text) {
            Ok(root) => root,
            Err(e) => {
                sink.parse(e.span(), e.message().trim().to_owned());
                return Err(TrackErrors {
                    errors: sink.errors,
                });
            }
        };
        let root_span = root.span();
        let mut table = root.into_inner();
        let segments_value = table.remove("segment");
        let irregularities_value = table.remove("irregularities");

        let mut segments = Vec::new();
        if let Some(value) = segments_value {
            let span = value.span();
            match value.into_inner() {
                DeValue::Array(items) => {
                    for (i, item) in items.iter().enumerate() {
                        match Spanned::<SegmentSpec>::deserialize(ValueDeserializer::from(
                            item.clone(),
                        )) {
                            Ok(seg) => segments.push(seg),
                            Err(e) => {
                                let key = e
                                    .span()
                                    .and_then(|sp| railsim_spec::key_at(item.get_ref(), sp.start));
                                sink.parse(
                                    e.span().or_else(|| Some(item.span())),
                                    format!("segment {}: {}", i + 1, with_key(key, e.message())),
                                )
                            }
                        }
                    }
                }
                other => sink.parse(
                    Some(span),
                    format!(
                        "segment: expected an array of tables ([[segment]]), found {}",
                        other.type_str()
                    ),
                ),
            }
        }

        let mut irregularities = None;
        if let Some(value) = irregularities_value {
            let span = value.span();
            let copy = value.clone();
            match Spanned::<IrregularitySpec>::deserialize(ValueDeserializer::from(value)) {
                Ok(irr) => irregularities = Some(irr),
                Err(e) => {
                    let key = e
                        .span()
                        .and_then(|sp| railsim_spec::key_at(copy.get_ref(), sp.start));
                    sink.parse(
                        e.span().or(Some(span)),
                        format!("irregularities: {}", with_key(key, e.message())),
                    )
                }
            }
        }

        let root_copy = DeValue::Table(table.clone());
        let root_result = TrackSpec::deserialize(toml::de::Deserializer::from(Spanned::new(
            root_span.clone(),
            table,
        )));
        let spec = match root_result {
            Ok(spec) => Some(spec),
            Err(e) => {
                let key = e
                    .span()
                    .and_then(|sp| railsim_spec::key_at(&root_copy, sp.start));
                sink.parse(
                    e.span().or(Some(root_span)),
                    with_key(key, &railsim_spec::friction_message(e.message())),
                );
                None
            }
        };
        sink.errors.sort_by_key(|e| match e {
            crate::TrackError::Parse { line, col, .. }
            | crate::TrackError::Invalid { line, col, .. } => (*line, *col),
            crate::TrackError::Io { .. } => (0, 0),
        });
        sink.finish()?;
        let mut spec = spec.ok_or_else(|| TrackErrors { errors: Vec::new() })?;
        spec.segment = segments;
        spec.irregularities = irregularities;
        spec.source = map;
        Ok(spec)
    }
}

/// Prefix a serde message with the key it is about, unless the message already names it.
fn with_key(key: Option<String>, message: &str) -> String {
    let message = message.trim();
    match key {
        Some(k) if !message.contains(&format!("`{k}`")) => format!("{k}: {message}"),
        _ => message.to_owned(),
    }
}
