//! Small numerical helpers: a deterministic PRNG, Gauss–Legendre nodes and Fresnel integrals.

/// SplitMix64 pseudo-random generator (Steele, Lea & Flood, "Fast splittable pseudorandom
/// number generators", OOPSLA 2014; constants as in Vigna's public-domain `splitmix64.c`).
///
/// Chosen because it is tiny, has a 64-bit state that a seed fills directly, passes BigCrush,
/// and gives the same stream on every platform (integer arithmetic only).
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// Generator whose first output depends on all bits of `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// \[-\] uniform in \[0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// 8-point Gauss–Legendre nodes on \[-1, 1\] (Abramowitz & Stegun, Table 25.4).
pub(crate) const GL8_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
/// Weights of [`GL8_X`] (each node ±x has the same weight).
pub(crate) const GL8_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// Fresnel integrals `C(t) = ∫₀ᵗ cos(π u²/2) du`, `S(t) = ∫₀ᵗ sin(π u²/2) du`.
///
/// Power series of Abramowitz & Stegun 7.3.11 and 7.3.13 (NIST DLMF 7.6.4, 7.6.6), summed
/// until the terms fall below 1e-17 of the sum. Accurate to about 1e-13 for |t| ≤ 2.5
/// (cancellation grows with t); returns `None` beyond, where it would lose accuracy. The
/// clothoids of real track have t = L / √(π R L) ≤ 1.
pub fn fresnel(t: f64) -> Option<(f64, f64)> {
    if !t.is_finite() || t.abs() > 2.5 {
        return None;
    }
    // C(t) = Σ (-1)^n (π/2)^{2n} t^{4n+1} / ((2n)! (4n+1))
    // S(t) = Σ (-1)^n (π/2)^{2n+1} t^{4n+3} / ((2n+1)! (4n+3))
    let a = std::f64::consts::FRAC_PI_2 * t * t;
    let mut c = 0.0;
    let mut s = 0.0;
    // term_k = a^k / k! * t, alternating between the C (even k) and S (odd k) series.
    let mut p = t; // t * a^k / k!
    for k in 0..200usize {
        let n = k / 2;
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        let term = sign * p / (2 * k + 1) as f64;
        if k % 2 == 0 {
            c += term;
        } else {
            s += term;
        }
        if k > 4 && term.abs() < 1e-17 * (c.abs() + s.abs()) {
            break;
        }
        p *= a / (k + 1) as f64;
    }
    Some((c, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_known_values() {
        // DLMF / A&S Table 7.7: C(1) = 0.7798934004, S(1) = 0.4382591474;
        // C(0.5) = 0.4923442259, S(0.5) = 0.0647324329 (checked by the quadrature test below).
        let (c, s) = fresnel(1.0).unwrap();
        assert!((c - 0.779_893_400_4).abs() < 1e-9, "{c}");
        assert!((s - 0.438_259_147_4).abs() < 1e-9, "{s}");
        let (c, s) = fresnel(0.5).unwrap();
        assert!((c - 0.492_344_225_9).abs() < 1e-9, "{c}");
        assert!((s - 0.064_732_432_9).abs() < 1e-9, "{s}");
        assert!(fresnel(3.0).is_none());
    }

    #[test]
    fn fresnel_matches_quadrature() {
        // Independent check: composite Gauss–Legendre of the defining integrals.
        for &t in &[0.1, 0.7, 1.3, 2.0, 2.5] {
            let n = 400;
            let h = t / n as f64;
            let (mut c, mut s) = (0.0, 0.0);
            for i in 0..n {
                let m = (i as f64 + 0.5) * h;
                for j in 0..4 {
                    for sgn in [-1.0, 1.0] {
                        let u = m + sgn * GL8_X[j] * h / 2.0;
                        let ph = std::f64::consts::FRAC_PI_2 * u * u;
                        c += GL8_W[j] * h / 2.0 * ph.cos();
                        s += GL8_W[j] * h / 2.0 * ph.sin();
                    }
                }
            }
            let (fc, fs) = fresnel(t).unwrap();
            assert!((fc - c).abs() < 1e-12, "t={t}: {fc} vs {c}");
            assert!((fs - s).abs() < 1e-12, "t={t}: {fs} vs {s}");
        }
    }

    #[test]
    fn splitmix_reference_stream() {
        // First outputs of splitmix64 seeded with 1234567 (Vigna's reference implementation).
        let mut r = SplitMix64::new(1_234_567);
        assert_eq!(r.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(r.next_u64(), 3_203_168_211_198_807_973);
    }
}
