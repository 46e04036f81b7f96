//! Shared set-up of the reference tests: the benchmark wheel/rail pair, reference tables,
//! tolerances.

use std::collections::HashMap;
use std::path::PathBuf;

use railsim_contact::contact_format::manchester_benchmark_pair;
use railsim_contact::{
    ContactModelKind, ContactOptions, PairSpec, WheelRailContact, WheelRailPair, WheelsetVelocity,
};

/// Path of a file in the repository.
pub fn repo(rel: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

/// The tolerance scale from `RAILSIM_TOL_SCALE` (default 1).
pub fn tol_scale() -> f64 {
    std::env::var("RAILSIM_TOL_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0)
}

/// Read `tests/reference/<case>/tolerances.toml`, table `section`, scaled.
pub fn tolerances(case: &str, section: &str) -> HashMap<String, f64> {
    let text =
        std::fs::read_to_string(repo(&format!("tests/reference/{case}/tolerances.toml"))).unwrap();
    let v: toml::Table = toml::from_str(&text).unwrap();
    let t = v[section].as_table().unwrap();
    t.iter()
        .map(|(k, v)| (k.clone(), v.as_float().unwrap() * tol_scale()))
        .collect()
}

/// The Manchester benchmark pair (CONTACT's mbench_a22 input): benchmark profile files, gauge
/// 1435 at 14 mm, no extra inclination, flange back 1360 at -70 mm, r0 = 460 mm, G = 82 GPa,
/// nu = 0.28, mu = 0.3.
pub fn mbench_pair() -> WheelRailPair {
    manchester_benchmark_pair(&repo("")).unwrap()
}

/// S1002 on UIC60 1:40, gauge 1435 mm, flange-back 1360 mm, r0 = 460 mm, analytic profiles
/// (`railsim contact`'s defaults).
pub fn standard_spec() -> PairSpec {
    PairSpec {
        wheel: railsim_profile::analytic::s1002(),
        rail: railsim_profile::analytic::uic60(),
        r0: 0.46,
        flange_back_distance: 1.36,
        flange_back_y: -0.07,
        gauge: 1.435,
        gauge_depth: 0.014,
        inclination: 1.0f64.atan2(40.0),
        material: railsim_elastic::Material::new(82e9, 0.28).unwrap(),
        friction: railsim_contact::Friction::Constant(0.3),
        curve_ds: 5e-5,
        smoothing: 0.0,
    }
}

/// The benchmark contact with a model and step (narrow-zone refinement as by default).
pub fn mbench_contact(model: ContactModelKind, step: f64) -> WheelRailContact {
    mbench_contact_with(model, step, ContactOptions::default().min_zone_pairs)
}

/// The benchmark contact with a model, step and narrow-zone refinement (0: the seed's fixed
/// step inside zones).
pub fn mbench_contact_with(
    model: ContactModelKind,
    step: f64,
    min_zone_pairs: usize,
) -> WheelRailContact {
    let mut opts = ContactOptions {
        model,
        min_zone_pairs,
        ..Default::default()
    };
    opts.travel.step = step;
    WheelRailContact::new(mbench_pair(), opts).unwrap()
}

/// A wheelset rolling at 30 m/s on the benchmark's 460 mm wheels, drifting sideways at 10 mm/s.
pub fn rolling_30_m_s() -> WheelsetVelocity {
    WheelsetVelocity {
        vx: 30.0,
        vy: 0.01,
        spin: -30.0 / 0.46,
        ..Default::default()
    }
}

/// A CSV table as header-indexed rows of strings.
pub struct Table {
    pub cols: HashMap<String, usize>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn read(rel: &str) -> Table {
        let text = std::fs::read_to_string(repo(rel)).unwrap();
        let mut lines = text.lines();
        let cols = lines
            .next()
            .unwrap()
            .split(',')
            .enumerate()
            .map(|(i, c)| (c.trim().to_string(), i))
            .collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|s| s.trim().to_string()).collect())
            .collect();
        Table { cols, rows }
    }
    pub fn f(&self, row: usize, col: &str) -> f64 {
        self.rows[row][self.cols[col]].parse().unwrap()
    }
    pub fn s(&self, row: usize, col: &str) -> &str {
        &self.rows[row][self.cols[col]]
    }
}

/// A small deterministic generator (64-bit LCG, Knuth's constants).
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}
