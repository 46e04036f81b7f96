//! Track irregularities: measured series (CSV) or synthetic series from the ERRI B176
//! spectra, stored as uniformly or non-uniformly sampled series and interpolated by cubic
//! Hermite polynomials: on a synthetic series with the exact slopes of its cosine sum, on a
//! measured one with the slopes of the parabolas through three neighbouring samples.
//!
//! # Spectra
//! One-sided PSDs in the angular wavenumber Ω \[rad/m\], S in m²/(rad/m), so that the variance
//! is σ² = ∫₀^∞ S(Ω) dΩ. With Ω_c = 0.8246 rad/m, Ω_r = 0.0206 rad/m, Ω_s = 0.4380 rad/m:
//!
//! - alignment (lateral) S_a = A_a Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²)),
//! - level (vertical) S_v = A_v Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²)),
//! - cross level S_c = (A_v / b²) Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²)) in rad²/(rad/m)
//!   for the cross-level angle, b = 0.75 m; as a height difference over 2b = 1.5 m it is
//!   (2b)² S_c,
//! - gauge S_g = A_g Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²)),
//!
//! | level | A_a \[m·rad\] | A_v \[m·rad\] | A_g \[m·rad\] |
//! |---|---|---|---|
//! | low | 2.119e-7 | 4.032e-7 | 0.532e-7 |
//! | high | 6.125e-7 | 10.80e-7 | 1.032e-7 |
//!
//! Sources and verification status are in `docs/models/track.md`: the lateral and vertical
//! spectra agree between two independent public sources (the SIMPACK QCH "ORE B176" predefined
//! coefficients as tabulated in a public code's documentation, and the "German" spectrum as
//! used in Chinese vehicle–track literature); cross level and gauge come from one source only
//! and are **unverified**.
//!
//! # Synthesis
//! Sum of N cosines per channel (Shinozuka & Jan 1972, "Digital simulation of random processes
//! and its applications", J. Sound Vib. 25(1)):
//! r(s) = Σₖ √(2 S(Ωₖ) ΔΩ) cos(Ωₖ (s − s₀) + θₖ), with the band \[Ω_min, Ω_max\] cut into N
//! equal bins of width ΔΩ, Ωₖ drawn uniformly inside bin k (which removes the period 2π/ΔΩ of
//! a regular grid) and θₖ uniform in \[0, 2π). Random numbers come from SplitMix64 seeded per
//! channel, so the same seed gives the same series bit for bit on one platform.

use std::f64::consts::PI;
use std::path::Path;

use crate::error::{TrackError, TrackErrors};
use crate::math::SplitMix64;
use railsim_spec::short_number;

/// \[rad/m\] Ω_c of the ERRI B176 spectra.
pub const ERRI_OMEGA_C: f64 = 0.8246;
/// \[rad/m\] Ω_r of the ERRI B176 spectra.
pub const ERRI_OMEGA_R: f64 = 0.0206;
/// \[rad/m\] Ω_s of the ERRI B176 cross-level and gauge spectra.
pub const ERRI_OMEGA_S: f64 = 0.4380;
/// \[m\] half base b of the ERRI B176 cross-level angle.
pub const ERRI_HALF_BASE: f64 = 0.75;

/// Irregularity channels, in the order of [`Irregularity`] and of the CSV columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Lateral alignment of the centre line (positive to the left).
    Lateral,
    /// Vertical level of the centre line (positive up).
    Vertical,
    /// Cross level: height of the left rail above the right one.
    CrossLevel,
    /// Gauge deviation from nominal (positive wider).
    Gauge,
}

impl Channel {
    /// All channels in storage order.
    pub const ALL: [Channel; 4] = [
        Channel::Lateral,
        Channel::Vertical,
        Channel::CrossLevel,
        Channel::Gauge,
    ];
}

/// A standard irregularity spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spectrum {
    /// ERRI B176 (ORE B176) "low level" spectrum (good track).
    ErriB176Low,
    /// ERRI B176 (ORE B176) "high level" spectrum (poorer track).
    ErriB176High,
}

impl Spectrum {
    /// Spectrum from its name in the track file (`erri_b176_low`, `erri_b176_high`).
    pub fn from_name(name: &str) -> Option<Spectrum> {
        match name {
            "erri_b176_low" => Some(Spectrum::ErriB176Low),
            "erri_b176_high" => Some(Spectrum::ErriB176High),
            _ => None,
        }
    }

    /// The names accepted by [`Spectrum::from_name`].
    pub const NAMES: [&'static str; 2] = ["erri_b176_low", "erri_b176_high"];

    /// (\[m·rad\] A_a, \[m·rad\] A_v, \[m·rad\] A_g).
    fn coefficients(self) -> (f64, f64, f64) {
        match self {
            Spectrum::ErriB176Low => (2.119e-7, 4.032e-7, 0.532e-7),
            Spectrum::ErriB176High => (6.125e-7, 10.80e-7, 1.032e-7),
        }
    }

    /// \[m²/(rad/m)\] one-sided PSD of `channel` at angular wavenumber `omega` \[rad/m\]
    /// (cross level as the height difference of the rails over 2b = 1.5 m).
    pub fn psd(self, channel: Channel, omega: f64) -> f64 {
        let (aa, av, ag) = self.coefficients();
        let w2 = omega * omega;
        let wc2 = ERRI_OMEGA_C * ERRI_OMEGA_C;
        let base = wc2 / ((w2 + ERRI_OMEGA_R * ERRI_OMEGA_R) * (w2 + wc2));
        let second = w2 / (w2 + ERRI_OMEGA_S * ERRI_OMEGA_S);
        match channel {
            Channel::Lateral => aa * base,
            Channel::Vertical => av * base,
            Channel::CrossLevel => {
                let angle = av / (ERRI_HALF_BASE * ERRI_HALF_BASE) * base * second;
                4.0 * ERRI_HALF_BASE * ERRI_HALF_BASE * angle
            }
            Channel::Gauge => ag * base * second,
        }
    }
}

/// The irregularity at one position, with d/ds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Irregularity {
    /// \[m\] lateral alignment of the centre line, positive to the left (track y).
    pub lateral: f64,
    /// \[m\] vertical level of the centre line, positive up (track z).
    pub vertical: f64,
    /// \[m\] cross level: height of the left rail above the right rail, beyond the design cant.
    pub cross_level: f64,
    /// \[m\] gauge deviation from nominal, positive when wider.
    pub gauge: f64,
    /// \[-\] d(lateral)/ds.
    pub dlateral_ds: f64,
    /// \[-\] d(vertical)/ds.
    pub dvertical_ds: f64,
    /// \[-\] d(cross_level)/ds.
    pub dcross_level_ds: f64,
    /// \[-\] d(gauge)/ds.
    pub dgauge_ds: f64,
}

/// Sampled irregularity series, four channels, in SI.
#[derive(Debug, Clone, PartialEq)]
pub struct IrregularitySeries {
    /// \[m\] sample positions (strictly increasing).
    s: Vec<f64>,
    /// \[m\] uniform step, when the samples are uniform (fast O(1) lookup).
    step: Option<f64>,
    /// \[m\] values per channel (lateral, vertical, cross level, gauge).
    values: [Vec<f64>; 4],
    /// \[-\] Hermite slopes per channel and sample.
    slopes: [Vec<f64>; 4],
}

impl IrregularitySeries {
    /// Series from samples (`s` strictly increasing, ≥ 2 samples). A sample's slope is that of
    /// the parabola through it and its two neighbours, (h₂d₁ + h₁d₂)/(h₁ + h₂) with d the
    /// divided differences on either side (the centred difference on a uniform grid; one-sided
    /// at the ends), so the interpolant is C¹ and exact for quadratics on any spacing.
    pub fn new(s: Vec<f64>, values: [Vec<f64>; 4]) -> IrregularitySeries {
        let n = s.len();
        let step = uniform_step(&s);
        let slopes = std::array::from_fn(|c| {
            let v = &values[c];
            (0..n)
                .map(|i| {
                    if n < 2 {
                        0.0
                    } else if i == 0 {
                        (v[1] - v[0]) / (s[1] - s[0])
                    } else if i == n - 1 {
                        (v[n - 1] - v[n - 2]) / (s[n - 1] - s[n - 2])
                    } else if step.is_some() {
                        (v[i + 1] - v[i - 1]) / (s[i + 1] - s[i - 1])
                    } else {
                        let (h1, h2) = (s[i] - s[i - 1], s[i + 1] - s[i]);
                        let (d1, d2) = ((v[i] - v[i - 1]) / h1, (v[i + 1] - v[i]) / h2);
                        (h2 * d1 + h1 * d2) / (h1 + h2)
                    }
                })
                .collect()
        });
        IrregularitySeries {
            s,
            step,
            values,
            slopes,
        }
    }

    /// Series from samples and their exact slopes \[-\] (a synthetic series, whose derivative is
    /// known in closed form).
    pub fn with_slopes(
        s: Vec<f64>,
        values: [Vec<f64>; 4],
        slopes: [Vec<f64>; 4],
    ) -> IrregularitySeries {
        IrregularitySeries {
            step: uniform_step(&s),
            s,
            values,
            slopes,
        }
    }

    /// The series faded in and out by a raised cosine over `taper` \[m\] at both ends of its
    /// range (a measured series that does not start and end at zero).
    pub fn tapered(self, taper: f64) -> IrregularitySeries {
        let (s0, s1) = (self.s[0], self.s[self.s.len() - 1]);
        let values = self.values.map(|v| {
            v.iter()
                .zip(&self.s)
                .map(|(&x, &si)| x * fade(si - s0, s1 - si, taper).0)
                .collect()
        });
        IrregularitySeries::new(self.s, values)
    }

    /// The first channel and end sample (index 0 or the last) whose value is further than
    /// `limit_mm` \[mm\] (a file limit, as [`CSV_END_MAX_MM`]) from zero, in channel order, the
    /// first sample before the last.
    pub fn end_beyond_mm(&self, limit_mm: f64) -> Option<(Channel, usize)> {
        let last = self.s.len().checked_sub(1)?;
        Channel::ALL.into_iter().find_map(|c| {
            let v = &self.values[c as usize];
            [0, last]
                .into_iter()
                .find(|&k| v[k].abs() * 1e3 > limit_mm)
                .map(|k| (c, k))
        })
    }

    /// \[m\] sample positions.
    pub fn positions(&self) -> &[f64] {
        &self.s
    }

    /// \[m\] samples of one channel.
    pub fn channel(&self, channel: Channel) -> &[f64] {
        &self.values[channel as usize]
    }

    /// Interpolated irregularity at s; zero outside the sampled range.
    pub fn at(&self, s: f64) -> Irregularity {
        let n = self.s.len();
        if n < 2 || !(s >= self.s[0] && s <= self.s[n - 1]) {
            return Irregularity::default();
        }
        let i = match self.step {
            Some(h) => (((s - self.s[0]) / h) as usize).min(n - 2),
            None => self.s.partition_point(|&x| x <= s).clamp(1, n - 1) - 1,
        };
        let h = self.s[i + 1] - self.s[i];
        let t = (s - self.s[i]) / h;
        // Cubic Hermite basis and derivatives.
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let d00 = (6.0 * t2 - 6.0 * t) / h;
        let d10 = 3.0 * t2 - 4.0 * t + 1.0;
        let d01 = (-6.0 * t2 + 6.0 * t) / h;
        let d11 = 3.0 * t2 - 2.0 * t;
        let mut v = [0.0; 4];
        let mut d = [0.0; 4];
        for c in 0..4 {
            let (y0, y1) = (self.values[c][i], self.values[c][i + 1]);
            let (m0, m1) = (self.slopes[c][i], self.slopes[c][i + 1]);
            v[c] = h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1;
            d[c] = d00 * y0 + d10 * m0 + d01 * y1 + d11 * m1;
        }
        Irregularity {
            lateral: v[0],
            vertical: v[1],
            cross_level: v[2],
            gauge: v[3],
            dlateral_ds: d[0],
            dvertical_ds: d[1],
            dcross_level_ds: d[2],
            dgauge_ds: d[3],
        }
    }
}

/// The grid step if `s` is uniform (to 1e-9 of the step), else `None`.
fn uniform_step(s: &[f64]) -> Option<f64> {
    let n = s.len();
    if n < 2 {
        return None;
    }
    let h = (s[n - 1] - s[0]) / (n - 1) as f64;
    s.iter()
        .enumerate()
        .all(|(i, &si)| (si - (s[0] + i as f64 * h)).abs() <= 1e-9 * h.max(1.0))
        .then_some(h)
}

/// The raised-cosine fade (g, dg/ds) at a point `from_start` and `to_end` \[m\] inside a
/// series' range: g = (1 − cos(π d/taper))/2 with d the distance to the nearer end, 1 beyond
/// `taper` (and for `taper` = 0).
fn fade(from_start: f64, to_end: f64, taper: f64) -> (f64, f64) {
    let (d, sign) = if from_start <= to_end {
        (from_start, 1.0)
    } else {
        (to_end, -1.0)
    };
    if taper > 0.0 && d < taper {
        let a = PI * d / taper;
        (0.5 - 0.5 * a.cos(), sign * 0.5 * PI / taper * a.sin())
    } else {
        (1.0, 0.0)
    }
}

/// Parameters of a synthetic irregularity, in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticParams {
    /// Spectrum.
    pub spectrum: Spectrum,
    /// Seed of the phases and wavenumbers.
    pub seed: u64,
    /// \[m\] shortest wavelength.
    pub wavelength_min: f64,
    /// \[m\] longest wavelength.
    pub wavelength_max: f64,
    /// \[m\] sampling step.
    pub step: f64,
    /// \[-\] number of cosines per channel.
    pub components: usize,
    /// \[m\] raised-cosine fade length at both ends.
    pub taper: f64,
    /// \[m\] start of the series.
    pub start: f64,
    /// \[m\] length of the series.
    pub length: f64,
}

/// Channel-specific seed: SplitMix64 of the seed XOR a per-channel constant, so the four
/// channels are independent streams.
fn channel_seed(seed: u64, channel: Channel) -> u64 {
    const SALT: [u64; 4] = [
        0x4C41_5445_5241_4C00, // "LATERAL\0"
        0x5645_5254_4943_414C, // "VERTICAL"
        0x4352_4F53_534C_564C, // "CROSSLVL"
        0x4741_5547_4500_0000, // "GAUGE\0\0\0"
    ];
    SplitMix64::new(seed ^ SALT[channel as usize]).next_u64()
}

/// Default number of cosines: frequency spacing 2π/(2·length) so that no period shows over the
/// series, at least 256.
pub fn default_components(wavelength_min: f64, wavelength_max: f64, length: f64) -> usize {
    let band = 2.0 * PI / wavelength_min - 2.0 * PI / wavelength_max;
    ((band * 2.0 * length / (2.0 * PI)).ceil() as usize).max(256)
}

/// One cosine of a synthetic channel: `amp cos(w s + theta)`.
#[derive(Clone, Copy)]
struct Cosine {
    w: f64,
    theta: f64,
    amp: f64,
}

/// Adds `N` cosines `amp cos(w·iΔ + θ)` to `out` and their derivatives `−amp w sin(w·iΔ + θ)` to
/// `slope` at the samples i = 0, 1, … (spacing `step`), by complex rotation re-anchored every 64
/// samples. The cosines are taken together sample by sample, each added in its own order, so that
/// every sample sums them as one at a time would, to the bit, while the `N` rotations overlap.
fn add_cosines<const N: usize>(cs: &[Cosine], step: f64, out: &mut [f64], slope: &mut [f64]) {
    let c: [Cosine; N] = std::array::from_fn(|j| cs[j]);
    let rot: [(f64, f64); N] = std::array::from_fn(|j| (c[j].w * step).sin_cos());
    let n = out.len();
    let mut i = 0;
    while i < n {
        let mut sc: [(f64, f64); N] =
            std::array::from_fn(|j| (c[j].w * i as f64 * step + c[j].theta).sin_cos());
        let end = (i + 64).min(n);
        for (o, d) in out[i..end].iter_mut().zip(&mut slope[i..end]) {
            for j in 0..N {
                let (sn, cs) = sc[j];
                let (rs, rc) = rot[j];
                *o += c[j].amp * cs;
                *d -= c[j].amp * c[j].w * sn;
                sc[j] = (sn * rc + cs * rs, cs * rc - sn * rs);
            }
        }
        i = end;
    }
}

/// Generate the four channels of a synthetic irregularity (sum of cosines, see the module
/// docs).
pub fn synthesize(p: &SyntheticParams) -> IrregularitySeries {
    let n = (p.length / p.step).round().max(1.0) as usize + 1;
    let step = p.length / (n - 1) as f64;
    let s: Vec<f64> = (0..n).map(|i| p.start + i as f64 * step).collect();
    let w_min = 2.0 * PI / p.wavelength_max;
    let w_max = 2.0 * PI / p.wavelength_min;
    let dw = (w_max - w_min) / p.components as f64;
    let mut slopes: [Vec<f64>; 4] = Default::default();
    let values = Channel::ALL.map(|channel| {
        let mut rng = SplitMix64::new(channel_seed(p.seed, channel));
        let comps: Vec<Cosine> = (0..p.components)
            .map(|k| {
                let w = w_min + (k as f64 + rng.next_f64()) * dw;
                let theta = 2.0 * PI * rng.next_f64();
                let amp = (2.0 * p.spectrum.psd(channel, w) * dw).sqrt();
                Cosine { w, theta, amp }
            })
            .collect();
        let mut out = vec![0.0; n];
        let mut slope = vec![0.0; n];
        let mut blocks = comps.chunks_exact(4);
        for block in blocks.by_ref() {
            add_cosines::<4>(block, step, &mut out, &mut slope);
        }
        for c in blocks.remainder() {
            add_cosines::<1>(std::slice::from_ref(c), step, &mut out, &mut slope);
        }
        if p.taper > 0.0 {
            for ((o, d), &si) in out.iter_mut().zip(&mut slope).zip(&s) {
                let (g, dg) = fade(si - p.start, p.start + p.length - si, p.taper);
                *d = *d * g + *o * dg;
                *o *= g;
            }
        }
        slopes[channel as usize] = slope;
        out
    });
    IrregularitySeries::with_slopes(s, values, slopes)
}

/// \[mm\] largest irregularity a measured CSV may give in any channel: poor track stays within
/// about 30 mm (EN 13848-5's immediate-action limits are below that); beyond it the value is a
/// unit or data error, and a wheelset would be pushed off the rails.
pub const CSV_MAX_VALUE_MM: f64 = 50.0;
/// \[m\] closest spacing of a measured CSV's rows (recording cars sample every 0.25–0.5 m).
pub const CSV_MIN_SPACING_M: f64 = 1e-3;
/// \[mm/m\] steepest change of a channel between two rows (10 %: a step that the vehicle would
/// meet as an impact, not an irregularity).
pub const CSV_MAX_SLOPE_MM_PER_M: f64 = 100.0;

/// \[mm\] largest value a measured CSV may start or end with when the track file sets no
/// `taper_m`: outside its range the irregularity is zero, and the vehicle meets the end value as
/// a step.
pub const CSV_END_MAX_MM: f64 = 0.1;

/// The columns a measured CSV must have, in this order.
pub const CSV_COLUMNS: [&str; 5] = [
    "distance_m",
    "lateral_mm",
    "vertical_mm",
    "cross_level_mm",
    "gauge_mm",
];

/// Read a measured irregularity CSV: a header line with [`CSV_COLUMNS`], then one row per
/// sample, distances strictly increasing. Lines starting with `#` and blank lines are skipped.
/// Every bad field is reported as `file:line:col`.
pub fn read_csv(path: &Path, display_name: &str) -> Result<IrregularitySeries, TrackErrors> {
    let text = std::fs::read_to_string(path).map_err(|e| TrackError::Io {
        file: display_name.to_owned(),
        message: e.to_string(),
    })?;
    parse_csv(&text, display_name)
}

/// Parse measured irregularity CSV text (see [`read_csv`]).
pub fn parse_csv(text: &str, file: &str) -> Result<IrregularitySeries, TrackErrors> {
    let mut errors = Vec::new();
    let err = |line: usize, col: usize, message: String| TrackError::Parse {
        file: file.to_owned(),
        line,
        col,
        message,
    };
    // (a byte-order mark, as spreadsheet programs write, is not part of the header)
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut s = Vec::new();
    let mut values: [Vec<f64>; 4] = Default::default();
    let mut header_seen = false;
    for (ln, line) in text.lines().enumerate() {
        let lineno = ln + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        // Fields with their 1-based start columns.
        let mut fields = Vec::with_capacity(5);
        let mut start = 0;
        for part in line.split(',') {
            let lead = part.len() - part.trim_start().len();
            fields.push((part.trim(), line[..start + lead].chars().count() + 1));
            start += part.len() + 1;
        }
        if !header_seen {
            header_seen = true;
            let names: Vec<&str> = fields.iter().map(|f| f.0).collect();
            if names != CSV_COLUMNS {
                errors.push(err(
                    lineno,
                    1,
                    format!(
                        "expected the header `{}`, found `{}`",
                        CSV_COLUMNS.join(","),
                        trimmed
                    ),
                ));
                break;
            }
            continue;
        }
        if fields.len() != 5 {
            errors.push(err(
                lineno,
                1,
                format!(
                    "expected 5 fields ({}), found {}",
                    CSV_COLUMNS.join(","),
                    fields.len()
                ),
            ));
            continue;
        }
        let mut row = [0.0; 5];
        let mut ok = true;
        for (c, &(f, col)) in fields.iter().enumerate() {
            match f.parse::<f64>() {
                Ok(v) if v.is_finite() => row[c] = v,
                _ => {
                    ok = false;
                    errors.push(err(
                        lineno,
                        col,
                        format!("{}: expected a finite number, found `{f}`", CSV_COLUMNS[c]),
                    ));
                }
            }
        }
        if !ok {
            continue;
        }
        if let Some(&last) = s.last()
            && row[0] <= last
        {
            errors.push(err(
                lineno,
                fields[0].1,
                format!(
                    "distance_m = {} must be greater than the previous row's {}",
                    short_number(row[0]),
                    short_number(last)
                ),
            ));
            continue;
        }
        if let Some(&last) = s.last()
            && row[0] - last < CSV_MIN_SPACING_M
        {
            errors.push(err(
                lineno,
                fields[0].1,
                format!(
                    "distance_m = {}: rows closer than {CSV_MIN_SPACING_M} m (previous row {})",
                    short_number(row[0]),
                    short_number(last)
                ),
            ));
            continue;
        }
        for c in 1..5 {
            let v = row[c];
            if v.abs() > CSV_MAX_VALUE_MM {
                ok = false;
                errors.push(err(
                    lineno,
                    fields[c].1,
                    format!(
                        "{} = {}: expected an irregularity within ±{CSV_MAX_VALUE_MM} mm (a unit error?)",
                        CSV_COLUMNS[c],
                        short_number(v)
                    ),
                ));
            } else if let (Some(&last), Some(&prev)) = (s.last(), values[c - 1].last()) {
                let slope = (v - prev * 1e3) / (row[0] - last);
                if slope.abs() > CSV_MAX_SLOPE_MM_PER_M {
                    ok = false;
                    errors.push(err(
                        lineno,
                        fields[c].1,
                        format!(
                            "{} = {v}: changes by {:.3} mm over {:.4} m from the previous row, steeper than {CSV_MAX_SLOPE_MM_PER_M} mm/m",
                            CSV_COLUMNS[c],
                            v - prev * 1e3,
                            row[0] - last
                        ),
                    ));
                }
            }
        }
        if !ok {
            continue;
        }
        s.push(row[0]);
        for c in 0..4 {
            values[c].push(row[c + 1] * 1e-3);
        }
    }
    if !header_seen {
        errors.push(err(
            1,
            1,
            format!(
                "expected the header `{}`, found an empty file",
                CSV_COLUMNS.join(",")
            ),
        ));
    } else if errors.is_empty() && s.len() < 2 {
        errors.push(err(
            text.lines().count().max(1),
            1,
            format!("expected at least 2 data rows, found {}", s.len()),
        ));
    }
    if errors.is_empty() {
        Ok(IrregularitySeries::new(s, values))
    } else {
        Err(TrackErrors { errors })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cosines taken four at a time give every sample's value and slope as one at a time
    /// does (the code before stop 34), to the bit, with a remainder block and with a fade.
    #[test]
    fn the_blocked_cosines_sum_as_one_at_a_time() {
        for (components, taper) in [(258, 0.0), (261, 20.0)] {
            let p = SyntheticParams {
                spectrum: Spectrum::ErriB176High,
                seed: 7,
                wavelength_min: 3.0,
                wavelength_max: 120.0,
                step: 0.25,
                components,
                taper,
                start: 10.0,
                length: 300.0,
            };
            let got = synthesize(&p);
            let n = got.s.len();
            let step = p.length / (n - 1) as f64;
            let w_min = 2.0 * PI / p.wavelength_max;
            let dw = (2.0 * PI / p.wavelength_min - w_min) / p.components as f64;
            for channel in Channel::ALL {
                let mut rng = SplitMix64::new(channel_seed(p.seed, channel));
                let (mut out, mut slope) = (vec![0.0; n], vec![0.0; n]);
                for k in 0..p.components {
                    let w = w_min + (k as f64 + rng.next_f64()) * dw;
                    let theta = 2.0 * PI * rng.next_f64();
                    let amp = (2.0 * p.spectrum.psd(channel, w) * dw).sqrt();
                    let (rs, rc) = (w * step).sin_cos();
                    let mut i = 0;
                    while i < n {
                        let (mut sn, mut cs) = (w * i as f64 * step + theta).sin_cos();
                        let end = (i + 64).min(n);
                        for (o, d) in out[i..end].iter_mut().zip(&mut slope[i..end]) {
                            *o += amp * cs;
                            *d -= amp * w * sn;
                            let c2 = cs * rc - sn * rs;
                            sn = sn * rc + cs * rs;
                            cs = c2;
                        }
                        i = end;
                    }
                }
                for ((o, d), &si) in out.iter_mut().zip(&mut slope).zip(&got.s) {
                    if p.taper > 0.0 {
                        let (g, dg) = fade(si - p.start, p.start + p.length - si, p.taper);
                        *d = *d * g + *o * dg;
                        *o *= g;
                    }
                }
                let c = channel as usize;
                for i in 0..n {
                    assert_eq!(
                        got.values[c][i].to_bits(),
                        out[i].to_bits(),
                        "{channel:?} {i}"
                    );
                    assert_eq!(
                        got.slopes[c][i].to_bits(),
                        slope[i].to_bits(),
                        "{channel:?} {i}"
                    );
                }
            }
        }
    }
}
