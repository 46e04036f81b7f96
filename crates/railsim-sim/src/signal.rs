//! Signal processing of sampled run outputs: Butterworth filters as cascades of second-order
//! sections, sliding means and r.m.s. values over windows of distance run, and the dominant
//! frequency of a signal. Nothing here knows of railways; [`crate::assess`] applies it to the
//! quantities of EN 14363.
//!
//! Sources of the formulas:
//! - second-order sections by the bilinear transform with the frequency pre-warped to the
//!   section's corner: R. Bristow-Johnson, *Cookbook formulae for audio equalizer biquad filter
//!   coefficients* (the low- and high-pass sections);
//! - an n-th order Butterworth filter is the cascade of n/2 such sections with the quality
//!   factors `Q_k = 1 / (2 cos((2k - 1) π / (2n)))`, k = 1..n/2, the pole pairs of the
//!   Butterworth polynomial (e.g. Oppenheim & Schafer, *Discrete-Time Signal Processing*,
//!   §7.1); for n = 4: 0.5412 and 1.3066;
//! - the periodogram with a Hann window (Oppenheim & Schafer §10.6).

/// One second-order section (biquad), direct form II transposed, with its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Biquad {
    b: [f64; 3],
    /// a1, a2 (a0 normalised to 1)
    a: [f64; 2],
    s: [f64; 2],
}

impl Biquad {
    /// A low-pass section with corner `fc` \[Hz\] and quality factor `q` at sample rate `fs`.
    fn lowpass(fc: f64, fs: f64, q: f64) -> Biquad {
        let (w, c) = corner(fc, fs);
        let alpha = w.sin() / (2.0 * q);
        Biquad::normalised(
            [(1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0],
            [1.0 + alpha, -2.0 * c, 1.0 - alpha],
        )
    }

    /// A high-pass section with corner `fc` \[Hz\] and quality factor `q` at sample rate `fs`.
    fn highpass(fc: f64, fs: f64, q: f64) -> Biquad {
        let (w, c) = corner(fc, fs);
        let alpha = w.sin() / (2.0 * q);
        Biquad::normalised(
            [(1.0 + c) / 2.0, -(1.0 + c), (1.0 + c) / 2.0],
            [1.0 + alpha, -2.0 * c, 1.0 - alpha],
        )
    }

    /// The analog section `(b0 + b1 s + b2 s²) / (a0 + a1 s + a2 s²)` by the bilinear transform
    /// `s = c (1 − z⁻¹) / (1 + z⁻¹)`.
    fn bilinear(b: [f64; 3], a: [f64; 3], c: f64) -> Biquad {
        let c2 = c * c;
        let z = |p: [f64; 3]| {
            [
                p[0] + p[1] * c + p[2] * c2,
                2.0 * (p[0] - p[2] * c2),
                p[0] - p[1] * c + p[2] * c2,
            ]
        };
        Biquad::normalised(z(b), z(a))
    }

    fn normalised(b: [f64; 3], a: [f64; 3]) -> Biquad {
        Biquad {
            b: [b[0] / a[0], b[1] / a[0], b[2] / a[0]],
            a: [a[1] / a[0], a[2] / a[0]],
            s: [0.0; 2],
        }
    }

    #[inline]
    fn step(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.s[0];
        self.s[0] = self.b[1] * x - self.a[0] * y + self.s[1];
        self.s[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// The digital corner frequency `w = 2π fc / fs` and its cosine.
fn corner(fc: f64, fs: f64) -> (f64, f64) {
    let w = 2.0 * std::f64::consts::PI * fc / fs;
    (w, w.cos())
}

/// Quality factors of the two sections of a 4th-order Butterworth filter.
const BUTTERWORTH4_Q: [f64; 2] = [0.541_196_100_146_197, 1.306_562_964_876_376_7];

/// A second-order analog section `(num[0] + num[1] s + num[2] s²) / (den[0] + den[1] s +
/// den[2] s²)`, s in rad/s, for [`Filter::from_analog`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogSection {
    /// Numerator coefficients, ascending powers of s.
    pub num: [f64; 3],
    /// Denominator coefficients, ascending powers of s.
    pub den: [f64; 3],
    /// \[Hz\] the frequency at which the digital section's response is made to equal the
    /// analog one (the bilinear transform pre-warped there); `None` or a frequency at or above
    /// 0.45 of the sample rate: not pre-warped.
    pub match_hz: Option<f64>,
}

/// A causal digital filter: a cascade of second-order sections.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    sections: Vec<Biquad>,
}

/// Why a filter cannot be made at a sample rate.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterError(pub String);

impl Filter {
    /// A 4th-order Butterworth low-pass filter with corner `fc` \[Hz\] (−3 dB) at sample rate
    /// `fs` \[Hz\]; the corner must lie below the Nyquist frequency `fs / 2`.
    pub fn lowpass4(fc: f64, fs: f64) -> Result<Filter, FilterError> {
        Filter::butterworth4(fc, fs, Biquad::lowpass)
    }

    /// A 4th-order Butterworth high-pass filter with corner `fc` \[Hz\] at sample rate `fs`.
    pub fn highpass4(fc: f64, fs: f64) -> Result<Filter, FilterError> {
        Filter::butterworth4(fc, fs, Biquad::highpass)
    }

    /// The two sections of a 4th-order Butterworth filter of kind `section`.
    fn butterworth4(
        fc: f64,
        fs: f64,
        section: fn(f64, f64, f64) -> Biquad,
    ) -> Result<Filter, FilterError> {
        check(fc, fs)?;
        Ok(Filter {
            sections: BUTTERWORTH4_Q.iter().map(|&q| section(fc, fs, q)).collect(),
        })
    }

    /// A band-pass filter from `f_lo` to `f_hi` \[Hz\]: the 4th-order Butterworth high-pass at
    /// `f_lo` followed by the 4th-order Butterworth low-pass at `f_hi` (−3 dB at both edges
    /// when they are an octave or more apart, a little more when closer).
    pub fn bandpass4(f_lo: f64, f_hi: f64, fs: f64) -> Result<Filter, FilterError> {
        if !(f_lo < f_hi && f_hi.is_finite()) {
            return Err(FilterError(format!(
                "the band's lower edge {f_lo} Hz is not below its upper edge {f_hi} Hz"
            )));
        }
        let mut f = Filter::highpass4(f_lo, fs)?;
        f.sections.extend(Filter::lowpass4(f_hi, fs)?.sections);
        Ok(f)
    }

    /// The digital counterpart of a cascade of analog second-order sections at sample rate
    /// `fs` \[Hz\], each by the bilinear transform (pre-warped at its `match_hz`).
    pub fn from_analog(sections: &[AnalogSection], fs: f64) -> Result<Filter, FilterError> {
        if !(fs.is_finite() && fs > 0.0) {
            return Err(FilterError(format!(
                "the sample rate {fs} Hz is not a positive number"
            )));
        }
        Ok(Filter {
            sections: sections
                .iter()
                .map(|q| {
                    let c = match q.match_hz {
                        Some(f) if f > 0.0 && f < 0.45 * fs => {
                            let w = 2.0 * std::f64::consts::PI * f;
                            w / (w / (2.0 * fs)).tan()
                        }
                        _ => 2.0 * fs,
                    };
                    Biquad::bilinear(q.num, q.den, c)
                })
                .collect(),
        })
    }

    /// The filter scaled so that its gain at `f` \[Hz\] (sample rate `fs`) is exactly 1 (a
    /// filter without gain there is returned as it is). The band-pass of [`Filter::bandpass4`]
    /// loses gain in its middle when its edges are closer than an octave (0.94 at 6 Hz for
    /// 4–8 Hz, 0.75 at 15 Hz for 13–17 Hz): scaled at the frequency it is meant to measure, a
    /// tone there passes whole.
    pub fn with_unit_gain_at(mut self, f: f64, fs: f64) -> Filter {
        let g = self.gain(f, fs);
        if let (true, Some(q)) = (g.is_finite() && g > 0.0, self.sections.first_mut()) {
            for b in &mut q.b {
                *b /= g;
            }
        }
        self
    }

    /// Filter `x` in place, causally, starting from the steady state of a constant input equal
    /// to `x[0]` (a run that starts with a steady force, e.g. in a curve, makes no start-up
    /// transient).
    pub fn apply(&self, x: &mut [f64]) {
        let mut sections = self.sections.clone();
        let mut u = x.first().copied().unwrap_or(0.0);
        for q in &mut sections {
            // DC gain of the section and the states that hold its output there
            let y = u * (q.b[0] + q.b[1] + q.b[2]) / (1.0 + q.a[0] + q.a[1]);
            q.s[1] = q.b[2] * u - q.a[1] * y;
            q.s[0] = q.b[1] * u - q.a[0] * y + q.s[1];
            u = y;
        }
        for v in x.iter_mut() {
            let mut y = *v;
            for s in &mut sections {
                y = s.step(y);
            }
            *v = y;
        }
    }

    /// The filter's gain at frequency `f` \[Hz\] (magnitude of its frequency response).
    pub fn gain(&self, f: f64, fs: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI * f / fs;
        // H(z) at z = e^{iw}: product of (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2)
        let (c1, s1, c2, s2) = (w.cos(), -w.sin(), (2.0 * w).cos(), -(2.0 * w).sin());
        self.sections.iter().fold(1.0, |g, q| {
            let num = (q.b[0] + q.b[1] * c1 + q.b[2] * c2).hypot(q.b[1] * s1 + q.b[2] * s2);
            let den = (1.0 + q.a[0] * c1 + q.a[1] * c2).hypot(q.a[0] * s1 + q.a[1] * s2);
            g * num / den
        })
    }
}

fn check(fc: f64, fs: f64) -> Result<(), FilterError> {
    if !(fs.is_finite() && fs > 0.0) {
        return Err(FilterError(format!(
            "the sample rate {fs} Hz is not a positive number"
        )));
    }
    if !(fc > 0.0 && fc < 0.5 * fs) {
        return Err(FilterError(format!(
            "a corner of {fc} Hz needs a sample rate above {} Hz (found {fs} Hz)",
            2.0 * fc
        )));
    }
    Ok(())
}

/// A statistic over one window of distance run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowValue {
    /// \[m\] distance run at the window's end.
    pub end: f64,
    /// The statistic over the window.
    pub value: f64,
}

/// Sliding means of `x` over windows of `window` distance, one ending every `step` of distance
/// (samples in order of non-decreasing distance `dist`). A window holds the samples with
/// `end - window < d <= end`; only whole windows (`end >= dist[0] + window`) are taken, and a
/// window without samples gives none.
///
/// The mean is over distance, as EN 14363's sliding means over 2 m of track: each sample
/// weighs half the distance from the sample before it to the one after it (the trapezoidal
/// rule; the first and the last sample the whole step to their neighbour), so that samples
/// taken at a constant rate count alike at a constant speed and a standstill's repeated samples
/// do not outweigh the track around them (a plain mean of the samples is a mean over time). A
/// window whose samples all weigh nothing (a standstill at the start) takes their plain mean.
pub fn sliding_mean(dist: &[f64], x: &[f64], window: f64, step: f64) -> Vec<WindowValue> {
    sliding(dist, x, window, step, |v| v)
}

/// Sliding root-mean-square values of `x`, windows as in [`sliding_mean`].
pub fn sliding_rms(dist: &[f64], x: &[f64], window: f64, step: f64) -> Vec<WindowValue> {
    let mut out = sliding(dist, x, window, step, |v| v * v);
    for w in &mut out {
        w.value = w.value.max(0.0).sqrt();
    }
    out
}

/// Sliding distance-weighted means of `f(x)` ([`sliding_mean`]): running sums over a window
/// that moves along the samples.
fn sliding(
    dist: &[f64],
    x: &[f64],
    window: f64,
    step: f64,
    f: impl Fn(f64) -> f64,
) -> Vec<WindowValue> {
    let n = dist.len().min(x.len());
    let mut out = Vec::new();
    if n == 0 || !(window > 0.0 && step > 0.0) {
        return out;
    }
    // the distance each sample weighs: half the run from the sample before it to the one after
    // it (the trapezoidal rule), at the ends the whole step to the neighbour
    let weight = |i: usize| {
        if n == 1 {
            1.0
        } else if i == 0 {
            dist[1] - dist[0]
        } else if i == n - 1 {
            dist[i] - dist[i - 1]
        } else {
            0.5 * (dist[i + 1] - dist[i - 1])
        }
    };
    let (first, last) = (dist[0], dist[n - 1]);
    // window ends at first + window + k step, within the samples; running sums of w f(x), w
    // and f(x)
    let (mut lo, mut hi) = (0usize, 0usize);
    let (mut sum, mut wsum, mut plain) = (0.0f64, 0.0f64, 0.0f64);
    let mut k = 0u64;
    loop {
        let end = first + window + k as f64 * step;
        if end > last + 1e-9 * window {
            break;
        }
        // (distances within a billionth of a window of an edge count as on it: a spacing
        // that divides the window then gives every window the same number of samples)
        let tol = 1e-9 * window;
        while hi < n && dist[hi] <= end + tol {
            let (w, v) = (weight(hi), f(x[hi]));
            (sum, wsum, plain) = (sum + w * v, wsum + w, plain + v);
            hi += 1;
        }
        while lo < hi && dist[lo] <= end - window + tol {
            let (w, v) = (weight(lo), f(x[lo]));
            (sum, wsum, plain) = (sum - w * v, wsum - w, plain - v);
            lo += 1;
        }
        if hi > lo {
            // (the running sums are recomputed now and then against round-off drift)
            if k % 1024 == 1023 {
                (sum, wsum, plain) = (lo..hi).fold((0.0, 0.0, 0.0), |(s, ws, p), i| {
                    let (w, v) = (weight(i), f(x[i]));
                    (s + w * v, ws + w, p + v)
                });
            }
            // (a weight below a billionth of the window is round-off of a standstill)
            let value = if wsum > 1e-9 * window {
                sum / wsum
            } else {
                plain / (hi - lo) as f64
            };
            out.push(WindowValue { end, value });
        }
        k += 1;
    }
    out
}

/// Most frequencies of the coarse grid of [`dominant_frequency`].
const COARSE_GRID: usize = 2000;

/// The frequency \[Hz\] of the largest peak of the Hann-windowed periodogram of `x` (sample
/// rate `fs`, mean removed) between `band.0` and `band.1` \[Hz\], to a tenth of the
/// periodogram's resolution `fs / n`: searched on a grid of that spacing, or for long signals
/// on a grid of 2000 frequencies refined around its peak (cost: n × at most 2040 terms);
/// `None` for fewer than 8 samples, a band outside `(0, fs / 2)` or a signal without power
/// there.
pub fn dominant_frequency(x: &[f64], fs: f64, band: (f64, f64)) -> Option<f64> {
    let n = x.len();
    let (f0, f1) = (band.0.max(0.0), band.1.min(0.5 * fs));
    if n < 8 || !(f0 < f1 && fs > 0.0) {
        return None;
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let two_pi = 2.0 * std::f64::consts::PI;
    let y: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let hann = 0.5 - 0.5 * (two_pi * i as f64 / (n - 1) as f64).cos();
            (v - mean) * hann
        })
        .collect();
    // Goertzel's recursion for the power at f
    let power = |f: f64| {
        let c = 2.0 * (two_pi * f / fs).cos();
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for &v in &y {
            let s = v + c * s1 - s2;
            s2 = s1;
            s1 = s;
        }
        s1 * s1 + s2 * s2 - c * s1 * s2
    };
    let fine = 0.1 * fs / n as f64;
    let df = fine.max((f1 - f0) / COARSE_GRID as f64);
    let best_on = |from: f64, to: f64, step: f64| {
        let steps = ((to - from) / step).ceil().max(1.0) as usize;
        (0..=steps)
            .map(|k| (from + k as f64 * step).min(to))
            .map(|f| (power(f), f))
            .fold((0.0f64, f64::NAN), |b, p| if p.0 > b.0 { p } else { b })
    };
    let mut best = best_on(f0, f1, df);
    if df > fine && best.0 > 0.0 {
        // the peak lies within a coarse step of the coarse grid's best
        best = best_on((best.1 - df).max(f0), (best.1 + df).min(f1), fine);
    }
    (best.0 > 0.0).then_some(best.1)
}

/// In-place radix-2 fast Fourier transform (`re`, `im` of a length that is a power of two):
/// X_k = Σ x_n e^{-2πi kn/N} (Cooley & Tukey, 1965; iterative, bit-reversed order first).
fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    debug_assert!(n.is_power_of_two() && im.len() == n);
    let mut j = 0usize;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * std::f64::consts::PI / len as f64;
        let (wr, wi) = (ang.cos(), ang.sin());
        for start in (0..n).step_by(len) {
            let (mut cr, mut ci) = (1.0f64, 0.0f64);
            for k in 0..len / 2 {
                let (a, b) = (start + k, start + k + len / 2);
                let (tr, ti) = (re[b] * cr - im[b] * ci, re[b] * ci + im[b] * cr);
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
                (cr, ci) = (cr * wr - ci * wi, cr * wi + ci * wr);
            }
        }
        len <<= 1;
    }
}

/// A one-sided power spectral density: `psd[k]` at frequency `k · df`.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// \[Hz\] frequency resolution.
    pub df: f64,
    /// One-sided density, (unit of the signal)² / Hz, from 0 to the Nyquist frequency.
    pub psd: Vec<f64>,
}

impl Spectrum {
    /// The integral of `weight(f)² · psd(f)` over `band` \[Hz\] (a sum over the bins in it).
    pub fn weighted_power(&self, band: (f64, f64), weight: impl Fn(f64) -> f64) -> f64 {
        self.psd
            .iter()
            .enumerate()
            .map(|(k, &g)| (k as f64 * self.df, g))
            .filter(|&(f, _)| f >= band.0 && f <= band.1)
            .map(|(f, g)| weight(f).powi(2) * g * self.df)
            .sum()
    }
}

/// Welch's estimate of the one-sided power spectral density of `x` (sample rate `fs`): the mean
/// of the Hann-windowed periodograms of segments of `segment` samples (a power of two; shorter
/// signals use the largest power of two they hold), spread evenly over the whole record and
/// overlapping by at least half, each segment's mean removed; scaled so that its integral is
/// the signal's variance (Welch, *IEEE Trans. Audio Electroacoustics* 15, 1967). `None` for
/// fewer than 16 samples.
pub fn welch_psd(x: &[f64], fs: f64, segment: usize) -> Option<Spectrum> {
    if x.len() < 16 || !(fs > 0.0 && segment >= 16) {
        return None;
    }
    let mut l = segment.next_power_of_two();
    while l > x.len() {
        l >>= 1;
    }
    let two_pi = 2.0 * std::f64::consts::PI;
    let w: Vec<f64> = (0..l)
        .map(|i| 0.5 - 0.5 * (two_pi * i as f64 / l as f64).cos())
        .collect();
    let w2: f64 = w.iter().map(|v| v * v).sum();
    let mut psd = vec![0.0; l / 2 + 1];
    let (mut re, mut im) = (vec![0.0; l], vec![0.0; l]);
    // segment starts spread evenly from the first sample to the last segment ending on the
    // last sample, at most half a segment apart (overlap at least half): the whole record
    // counts (before stop 45 the starts stepped by half a segment from 0 and the tail that no
    // whole step reached, up to a third of a 23.6 s run, was left out)
    let spare = x.len() - l;
    let segments = spare.div_ceil(l / 2) + 1;
    for k in 0..segments {
        let start = if segments > 1 {
            ((k * spare) as f64 / (segments - 1) as f64).round() as usize
        } else {
            0
        };
        let seg = &x[start..start + l];
        let mean = seg.iter().sum::<f64>() / l as f64;
        for i in 0..l {
            re[i] = (seg[i] - mean) * w[i];
            im[i] = 0.0;
        }
        fft(&mut re, &mut im);
        for (k, p) in psd.iter_mut().enumerate() {
            *p += re[k] * re[k] + im[k] * im[k];
        }
    }
    let scale = 1.0 / (fs * w2 * segments as f64);
    let last = psd.len() - 1;
    for (k, p) in psd.iter_mut().enumerate() {
        // one-sided: the negative frequencies folded in, except at 0 and Nyquist
        *p *= if k == 0 || k == last {
            scale
        } else {
            2.0 * scale
        };
    }
    Some(Spectrum {
        df: fs / l as f64,
        psd,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(f: f64, fs: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * f * i as f64 / fs).sin())
            .collect()
    }

    /// Amplitude (√2 × r.m.s. over the last 2000 samples, a whole number of periods in the
    /// tests) of a unit sine after the filter has settled.
    fn amplitude_after(filter: &Filter, f: f64, fs: f64) -> f64 {
        let n = (fs * 40.0 / f.min(1.0)) as usize + 4000;
        let mut x = sine(f, fs, n);
        filter.apply(&mut x);
        let tail = &x[n - 2000..];
        (2.0 * tail.iter().map(|v| v * v).sum::<f64>() / tail.len() as f64).sqrt()
    }

    #[test]
    fn butterworth_low_pass_is_3_db_down_at_its_corner_and_flat_below() {
        let fs = 200.0;
        let lp = Filter::lowpass4(20.0, fs).unwrap();
        let half = std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            (lp.gain(20.0, fs) - half).abs() < 1e-9,
            "{}",
            lp.gain(20.0, fs)
        );
        assert!((lp.gain(0.0, fs) - 1.0).abs() < 1e-12);
        // 4th order: -24 dB per octave well above the corner (bilinear: steeper near Nyquist)
        assert!(lp.gain(40.0, fs) < 0.07, "{}", lp.gain(40.0, fs));
        // the time-domain response agrees with the frequency response
        for f in [2.0, 20.0, 35.0] {
            let a = amplitude_after(&lp, f, fs);
            assert!((a - lp.gain(f, fs)).abs() < 2e-3, "{f} Hz: {a}");
        }
    }

    #[test]
    fn butterworth_band_pass_keeps_its_band_and_rejects_the_rest() {
        let fs = 200.0;
        let bp = Filter::bandpass4(3.0, 7.0, fs).unwrap();
        // the two 4th-order edges 1.2 octaves apart: -3 dB at the edges, a 4 % dip between
        let half = std::f64::consts::FRAC_1_SQRT_2;
        for edge in [3.0, 7.0] {
            assert!(
                (bp.gain(edge, fs) - half).abs() < 0.01,
                "{}",
                bp.gain(edge, fs)
            );
        }
        assert!(
            (0.95..1.0).contains(&bp.gain(5.0, fs)),
            "{}",
            bp.gain(5.0, fs)
        );
        assert!(bp.gain(0.0, fs) < 1e-12);
        // 4th order: about (1/3)^4 and (7/20)^4 an octave and more outside
        assert!(bp.gain(1.0, fs) < 0.015, "{}", bp.gain(1.0, fs));
        assert!(bp.gain(20.0, fs) < 0.016, "{}", bp.gain(20.0, fs));
        let a = amplitude_after(&bp, 5.0, fs);
        assert!((a - bp.gain(5.0, fs)).abs() < 2e-3, "{a}");
        let hp = Filter::highpass4(3.0, fs).unwrap();
        assert!((hp.gain(3.0, fs) - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
    }

    #[test]
    fn a_constant_input_passes_without_a_start_up_transient() {
        let fs = 200.0;
        let mut x = vec![5.0; 400];
        Filter::lowpass4(20.0, fs).unwrap().apply(&mut x);
        assert!(x.iter().all(|v| (v - 5.0).abs() < 1e-9), "{:?}", &x[..5]);
        let mut x = vec![5.0; 400];
        Filter::bandpass4(3.0, 7.0, fs).unwrap().apply(&mut x);
        assert!(x.iter().all(|v| v.abs() < 1e-9), "{:?}", &x[..5]);
        // a step after the start still rings as a 4th-order Butterworth does (about 11 %)
        let mut x: Vec<f64> = (0..400).map(|i| if i < 100 { 0.0 } else { 1.0 }).collect();
        Filter::lowpass4(20.0, fs).unwrap().apply(&mut x);
        let peak = x.iter().fold(0.0f64, |m, &v| m.max(v));
        assert!((1.08..1.14).contains(&peak), "{peak}");
    }

    #[test]
    fn filters_reject_corners_the_sample_rate_cannot_carry() {
        let e = Filter::lowpass4(20.0, 30.0).unwrap_err();
        assert!(
            e.0.contains("above 40 Hz") && e.0.contains("30 Hz"),
            "{}",
            e.0
        );
        assert!(Filter::bandpass4(5.0, 3.0, 200.0).is_err());
        assert!(Filter::lowpass4(20.0, f64::NAN).is_err());
    }

    #[test]
    fn sliding_windows_cover_their_distance_whatever_the_spacing() {
        // x = d: the mean over (end - 2, end] of evenly spaced samples is end - 1 (+ half a
        // spacing's bias), the r.m.s. of a constant is the constant
        let dist: Vec<f64> = (0..=400).map(|i| i as f64 * 0.25).collect();
        let m = sliding_mean(&dist, &dist, 2.0, 0.5);
        assert_eq!(m.len(), ((100.0 - 2.0) / 0.5) as usize + 1);
        assert!((m[0].end - 2.0).abs() < 1e-12);
        for w in &m {
            // samples end - 1.75 .. end: mean end - 0.875
            assert!((w.value - (w.end - 0.875)).abs() < 1e-9, "{w:?}");
        }
        let ones = vec![-3.0; dist.len()];
        let r = sliding_rms(&dist, &ones, 10.0, 1.0);
        assert!(r.iter().all(|w| (w.value - 3.0).abs() < 1e-12));
        // a run shorter than one window gives none
        assert!(sliding_mean(&dist[..5], &dist[..5], 2.0, 0.5).is_empty());
        // spacing wider than the window: windows without samples are skipped
        let sparse = [0.0, 3.0, 6.0];
        let m = sliding_mean(&sparse, &sparse, 2.0, 0.5);
        assert!(m.iter().all(|w| w.value == 3.0 || w.value == 6.0), "{m:?}");
    }

    #[test]
    fn sliding_means_are_over_distance_at_a_varying_speed() {
        // Samples at 1 kHz: 40 m/s for 1 s, then 10 m/s, with a standstill of 2 s at 50 m;
        // x = 1 while running at 40 m/s, 0 after. The 2 m window ending 1 m after the speed
        // change holds 1 m of each: a mean over distance of 0.5, where the mean of the samples
        // (24 of its 125 samples at 40 m/s) is 0.19.
        let (mut dist, mut x) = (vec![], vec![]);
        let mut d = 0.0;
        for i in 0..8000 {
            let t = i as f64 * 1e-3;
            let v = if t < 1.0 {
                40.0
            } else if (2.0..4.0).contains(&t) {
                0.0
            } else {
                10.0
            };
            dist.push(d);
            x.push(if t < 1.0 { 1.0 } else { 0.0 });
            d += v * 1e-3;
        }
        let m = sliding_mean(&dist, &x, 2.0, 0.5);
        let at = |m: &[WindowValue], end: f64| {
            m.iter().find(|w| (w.end - end).abs() < 1e-9).unwrap().value
        };
        // (the change at 40 m falls between two samples 0.04 m apart: 0.49 by the trapezoids)
        assert!((at(&m, 41.0) - 0.5).abs() < 0.02, "{}", at(&m, 41.0));
        // The standstill's 2000 samples at 50 m count for no distance: with x = distance, the
        // window (48.5, 50.5] has the mean of the track it covers, 49.505 (its samples every
        // 0.01 m from 48.51 on), where the plain mean of its samples is 49.955.
        let m = sliding_mean(&dist, &dist, 2.0, 0.5);
        assert!((at(&m, 50.5) - 49.505).abs() < 1e-6, "{}", at(&m, 50.5));
    }

    #[test]
    fn the_fft_matches_the_direct_transform() {
        let x: Vec<f64> = (0..16)
            .map(|i| ((i * 7 % 5) as f64 - 2.0) * 0.3 + i as f64 * 0.1)
            .collect();
        let (mut re, mut im) = (x.clone(), vec![0.0; 16]);
        fft(&mut re, &mut im);
        for k in 0..16 {
            let (mut a, mut b) = (0.0, 0.0);
            for (n, v) in x.iter().enumerate() {
                let ang = -2.0 * std::f64::consts::PI * (k * n) as f64 / 16.0;
                a += v * ang.cos();
                b += v * ang.sin();
            }
            assert!(
                (re[k] - a).abs() < 1e-12 && (im[k] - b).abs() < 1e-12,
                "{k}"
            );
        }
    }

    #[test]
    fn welch_spectra_integrate_to_the_variance() {
        let fs = 200.0;
        // a sine of amplitude 2 at 3 Hz: variance 2, its power within a few bins of 3 Hz
        let x: Vec<f64> = sine(3.0, fs, 20_000)
            .iter()
            .map(|v| 2.0 * v + 5.0)
            .collect();
        let s = welch_psd(&x, fs, 4096).unwrap();
        assert!((s.df - fs / 4096.0).abs() < 1e-12);
        let total = s.weighted_power((0.0, 100.0), |_| 1.0);
        assert!((total - 2.0).abs() < 0.01, "{total}");
        let near = s.weighted_power((2.8, 3.2), |_| 1.0);
        assert!(near > 0.99 * total, "{near}");
        // a deterministic broadband signal: the integral is its variance (Parseval, to the
        // windows' averaging)
        let mut state = 12345u64;
        let noise: Vec<f64> = (0..40_000)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            })
            .collect();
        let var = noise.iter().map(|v| v * v).sum::<f64>() / noise.len() as f64;
        let s = welch_psd(&noise, fs, 1024).unwrap();
        let total = s.weighted_power((0.0, 100.0), |_| 1.0);
        assert!((total / var - 1.0).abs() < 0.03, "{total} {var}");
        assert!(welch_psd(&noise[..10], fs, 1024).is_none());
    }

    #[test]
    fn the_dominant_frequency_of_a_noisy_sine_is_found_within_the_grid() {
        let fs = 200.0;
        let n = 4000; // 20 s: resolution 0.05 Hz, grid 0.005 Hz
        let mut x = sine(4.37, fs, n);
        // a weaker tone outside the band, another inside it, and a deterministic "noise"
        for (i, v) in x.iter_mut().enumerate() {
            let t = i as f64 / fs;
            *v += 3.0 * (2.0 * std::f64::consts::PI * 0.4 * t).sin()
                + 0.3 * (2.0 * std::f64::consts::PI * 9.0 * t).sin()
                + 0.2 * ((i * 7919 % 1000) as f64 / 1000.0 - 0.5);
        }
        let f = dominant_frequency(&x, fs, (1.0, 15.0)).unwrap();
        assert!((f - 4.37).abs() < 0.01, "{f}");
        // a long signal: the coarse grid (2000 points over the band) and its refinement
        let long: Vec<f64> = (0..60_000)
            .map(|i| (2.0 * std::f64::consts::PI * 4.3712 * i as f64 / fs).sin())
            .collect();
        let f = dominant_frequency(&long, fs, (1.0, 15.0)).unwrap();
        assert!((f - 4.3712).abs() < 3e-4, "{f}");
        assert_eq!(dominant_frequency(&x[..4], fs, (1.0, 15.0)), None);
        assert_eq!(dominant_frequency(&vec![1.0; 100], fs, (1.0, 15.0)), None);
    }
}
