//! One interface for a ladder of contact models, from fastest to most exact.
//!
//! Every model takes the same input (one patch found by the isosceles travelling, with its
//! kinematics) and gives the same output ([`PatchForces`]). The geometry stage is shared; only
//! the normal and tangential solution differ:
//!
//! | name | normal problem | tangential problem |
//! |---|---|---|
//! | `linear` | Hertz ellipse per patch | Kalker's linear theory, or a constant creep coefficient (Wickens) |
//! | `polach` | Hertz ellipse per patch from the rigid pair's curvatures and penetration | Polach (1999/2005) |
//! | `fastsim` | Hertz ellipse per patch | FASTSIM (Kalker 1982) on the ellipse |
//! | `stripes` | STRIPES on the isosceles strips (Ayasse & Chollet 2005; Jalili & Salehi 2011) | FaStrip (default) or FASTSIM per strip |
//! | `halfspace` | Boussinesq–Love half-space (Kalker's NORM; Polonsky & Keer CG) on the patch's gap | FaStrip (default) or FASTSIM per grid row |

use railsim_elastic::{
    Creepages, Grid, HalfspaceSolver, PolachParams, TangentialForces, TractionBound,
    blended_flexibilities, fastsim_ellipse, hertz_coeffs_fast, hertz_from_approach, linear_kalker,
    polach, spin_corrected_creepage,
};

use crate::broad::{BroadMemory, BroadScratch};
use crate::error::ContactError;
use crate::friction::FallingFriction;
use crate::geometry::{
    IsoPair, PoseCtx, TravelOptions, TravelStats, Zone, find_zones, locus, refine_narrow_zones,
    travel,
};
use crate::pair::WheelRailPair;
use crate::patch::{
    PatchFrame, WheelKinematics, from_plane_to_frame, longitudinal_curvature, patch_frame,
    reference_point, spin_moment_moved,
};
use crate::point;

/// \[-\] the last lowering of the load control's bracket, as a fraction of the largest
/// interpenetration allowed (`ContactOptions::max_penetration`): just inside it.
const LAST_LOWERING: f64 = 0.999;
use crate::pose::{Side, WheelsetPose, WheelsetVelocity};
use crate::stripes::{self, Local, Strip, StripesVariant, Tangential};
use crate::warm::WarmStart;
use crate::wells::{WellScratch, split_into_wells};

/// The contact models, selected by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactModelKind {
    /// Hertz ellipse per patch + Kalker's linear creep theory (no saturation): Kalker's
    /// coefficients C11, C22, C23, C33 (J.J. Kalker, 1967), or a constant creep coefficient
    /// f11 = f22 = f with no spin terms ([`ContactOptions::linear_creep`]), the model of the
    /// classical linear stability analyses (A.H. Wickens, Fundamentals of Rail Vehicle Dynamics,
    /// 2003). For analytic checks and linearised studies, not for curving with flange contact.
    Linear,
    /// Hertz ellipse per patch + Polach's creep-force formulas (O. Polach, VSD 33 suppl. 1999;
    /// Wear 258, 2005). The fastest level.
    Polach,
    /// Hertz ellipse per patch + FASTSIM (J.J. Kalker, VSD 11, 1982).
    Fastsim,
    /// The seed's model: isosceles strips + STRIPES (J.B. Ayasse, H. Chollet, VSD 43, 2005;
    /// M.M. Jalili, H. Salehi 2011) + FaStrip (or FASTSIM) per strip. The default.
    Stripes,
    /// Half-space boundary elements for the normal problem (Love 1929 influence coefficients,
    /// Polonsky & Keer, Wear 231, 1999) + FaStrip (or FASTSIM) per grid row: the reference
    /// normal level.
    Halfspace,
}

impl ContactModelKind {
    /// All models, fastest first.
    pub const ALL: [ContactModelKind; 5] = [
        ContactModelKind::Linear,
        ContactModelKind::Polach,
        ContactModelKind::Fastsim,
        ContactModelKind::Stripes,
        ContactModelKind::Halfspace,
    ];
    /// Whether the model solves each well with a Hertz ellipse (`linear`, `polach`, `fastsim`).
    pub fn is_hertz(self) -> bool {
        matches!(
            self,
            ContactModelKind::Linear | ContactModelKind::Polach | ContactModelKind::Fastsim
        )
    }
    /// The model's name as used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ContactModelKind::Linear => "linear",
            ContactModelKind::Polach => "polach",
            ContactModelKind::Fastsim => "fastsim",
            ContactModelKind::Stripes => "stripes",
            ContactModelKind::Halfspace => "halfspace",
        }
    }
    /// Parse a model name.
    pub fn from_name(name: &str) -> Result<Self, ContactError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| ContactError::BadOption {
                key: "model",
                value: name.to_string(),
                expected: "one of linear, polach, fastsim, stripes, halfspace".into(),
            })
    }
}

/// Options of a contact evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// Which model solves the patches.
    pub model: ContactModelKind,
    /// Travelling (geometry) options.
    pub travel: TravelOptions,
    /// \[rad\] the Hertz models' travelled runs (`HertzSearch::Travel`): a penetrated run is split
    /// into two zones only if the contact angles of its two penetration maxima differ by more
    /// than this; each zone is then cut into wells (`crate::wells`). STRIPES and `halfspace` cut
    /// runs into coupled wells instead.
    pub split_angle: f64,
    /// \[-\] ... and the penetration between them falls below this fraction of the smaller maximum
    pub split_depth_ratio: f64,
    /// A zone resolved by fewer travelled pairs than this is travelled again with a finer step
    /// (narrow flange-root and flange patches); 0 disables the refinement. STRIPES counts the
    /// pairs in the zone's contact (`(1 - eps0) delta0` deep), the other models all its pairs.
    pub min_zone_pairs: usize,
    /// Which virtual-penetration ratio STRIPES uses.
    pub stripes_variant: StripesVariant,
    /// Tangential solution per strip (`stripes`) or per grid row (`halfspace`).
    pub tangential: Tangential,
    /// FASTSIM cells per strip (along x)
    pub fastsim_nx: usize,
    /// FASTSIM strips for a Hertz ellipse (`fastsim` model)
    pub fastsim_ny: usize,
    /// Traction bound of FASTSIM.
    pub bound: TractionBound,
    /// Half-space grid: cells along x and along the lateral coordinate.
    pub halfspace_cells: (usize, usize),
    /// Grid of the exact tangential solution on a STRIPES patch ([`Tangential::Exact`]): cells
    /// along x and along the lateral coordinate. (`halfspace` solves it on its own grid.)
    pub exact_cells: (usize, usize),
    /// \[m\] interpenetration beyond which a pose is rejected as absurd
    pub max_penetration: f64,
    /// \[N\] `linear` model only: a constant creep coefficient f11 = f22 = f of the wheel with
    /// f23 = f33 = 0 (no spin), instead of Kalker's coefficients of the Hertz ellipse; a wheel
    /// with several patches shares it in proportion to their normal forces.
    pub linear_creep: Option<f64>,
    /// How the Hertz models (`linear`, `polach`, `fastsim`) find their contact points.
    pub hertz_search: HertzSearch,
    /// `polach` model only: Polach's reduction factors; the default is his 1999 model.
    pub polach: PolachAdhesion,
    /// Friction falling with the slip velocity (`polach`, `fastsim`, and `stripes` with a
    /// FASTSIM-type tangential solution); the default is Coulomb friction.
    pub falling_friction: FallingFriction,
}

/// Polach's extended creep-force model (Polach, Wear 258, 2005, eqs. 2 and 3; the kernel
/// `railsim_elastic::polach`): the reduction factors `k_A` of the initial slope in the adhesion
/// area and `k_S` in the slip area. With them goes the friction falling with the slip
/// velocity of his model, [`ContactOptions::falling_friction`]. Polach's 1999 model is
/// `k_A = k_S = 1` (the default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolachAdhesion {
    /// \[-\] reduction factor `k_A` of the initial slope, in (0, 1]
    pub k_a: f64,
    /// \[-\] reduction factor `k_S` in the slip area, in (0, `k_a`]
    pub k_s: f64,
}

impl Default for PolachAdhesion {
    fn default() -> Self {
        PolachAdhesion { k_a: 1.0, k_s: 1.0 }
    }
}

impl PolachAdhesion {
    /// The first parameter out of its range, as (key, value found, what is expected): `k_a` in
    /// (0, 1], `k_s` in (0, `k_a`] (Polach's k_S ≤ k_A ≤ 1).
    pub fn problem(&self) -> Option<(&'static str, String, &'static str)> {
        let in_unit = |x: f64| x > 0.0 && x <= 1.0;
        if !in_unit(self.k_a) {
            Some(("polach k_a", self.k_a.to_string(), "a factor in (0, 1]"))
        } else if !(self.k_s > 0.0 && self.k_s <= self.k_a) {
            Some(("polach k_s", self.k_s.to_string(), "a factor in (0, k_a]"))
        } else {
            None
        }
    }

    /// The kernel's parameters at the patch friction `mu0` with the falling friction `falling`.
    fn at(&self, mu0: f64, falling: &FallingFriction) -> PolachParams {
        PolachParams {
            k_a: self.k_a,
            k_s: self.k_s,
            mu0,
            a_ratio: falling.ratio,
            b_decay: falling.decay,
        }
    }
}

/// How the Hertz models find the contact point of each zone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HertzSearch {
    /// The single-point search: the bounding hierarchies of the profiles and a Newton search for
    /// the rigid contact pair of each zone (`crate::point`), no travelling.
    #[default]
    Point,
    /// The seed's travelling, as for STRIPES, and the deepest travelled pair of each zone.
    Travel,
}

impl HertzSearch {
    /// Parse `point` or `travel`.
    pub fn from_name(name: &str) -> Result<Self, ContactError> {
        match name {
            "point" => Ok(HertzSearch::Point),
            "travel" => Ok(HertzSearch::Travel),
            _ => Err(ContactError::BadOption {
                key: "hertz_search",
                value: name.to_string(),
                expected: "point or travel".into(),
            }),
        }
    }

    /// The name [`from_name`](Self::from_name) reads.
    pub fn name(self) -> &'static str {
        match self {
            HertzSearch::Point => "point",
            HertzSearch::Travel => "travel",
        }
    }
}

impl Default for ContactOptions {
    fn default() -> Self {
        ContactOptions {
            model: ContactModelKind::Stripes,
            travel: TravelOptions::default(),
            split_angle: 0.1,
            split_depth_ratio: 0.5,
            min_zone_pairs: 12,
            stripes_variant: StripesVariant::LocalEpsilon,
            tangential: Tangential::Fastrip,
            fastsim_nx: 16,
            fastsim_ny: 16,
            bound: TractionBound::Elliptic,
            halfspace_cells: (48, 48),
            exact_cells: (32, 32),
            max_penetration: 5e-3,
            linear_creep: None,
            hertz_search: HertzSearch::Point,
            polach: PolachAdhesion::default(),
            falling_friction: FallingFriction::default(),
        }
    }
}

/// The tangential solution on a Hertz ellipse.
#[derive(Clone, Copy, Debug, PartialEq)]
enum HertzTangential {
    /// Kalker's linear theory, or the constant creep coefficient of
    /// [`ContactOptions::linear_creep`] shared by the wheel's patches: `wheel_fn` \[N\] is the
    /// sum of their normal forces (0 for a single patch).
    Linear {
        wheel_fn: f64,
    },
    Polach,
    Fastsim,
}

/// Everything a model needs to solve one patch.
pub struct PatchInput<'a> {
    /// The wheel/rail pair.
    pub pair: &'a WheelRailPair,
    /// All travelled pairs of this wheel.
    pub pairs: &'a [IsoPair],
    /// The zone of this patch within `pairs`.
    pub zone: Zone,
    /// The rigid contact pair and patch frame.
    pub frame: PatchFrame,
    /// Wheel kinematics for creepages.
    pub kin: &'a WheelKinematics,
    /// Creepages at the reference point.
    pub creep: Creepages,
    /// The patch reference point and its contact angle ([`reference_point`]): where the patch
    /// is reported, the plane of the half-space patch and of the exact tangential solution.
    pub reference: (IsoPair, f64),
    /// The pose's locus map (rotation, yaw), for the yawed locus' curvature.
    pub(crate) ctx: crate::geometry::PoseCtx,
}

impl PatchInput<'_> {
    /// The pairs of the zone plus one on each side (for the edge interpolation).
    pub fn pair_range(&self) -> (usize, usize) {
        (
            self.zone.first.saturating_sub(1),
            (self.zone.last + 1).min(self.pairs.len() - 1),
        )
    }
}

/// Forces of one patch on the wheel, in the patch axes (x along the track, s lateral in the
/// contact plane toward the field side, n normal from rail to wheel).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PatchForces {
    /// \[N\] normal force (compressive positive)
    pub fn_: f64,
    /// \[N\] longitudinal creep force on the wheel
    pub fx: f64,
    /// \[N\] lateral creep force on the wheel, along s
    pub fs: f64,
    /// \[N m\] spin moment on the wheel about the normal through the reference point
    pub mz: f64,
    /// \[Pa\] maximum pressure
    pub p_max: f64,
    /// \[m\] patch length along x
    pub length: f64,
    /// \[m\] patch width along s
    pub width: f64,
    /// \[m^2\] contact area
    pub area: f64,
    /// \[-\] fraction of the contact in adhesion
    pub adhesion_fraction: f64,
    /// number of strips, grid cells in contact, or 1 for an ellipse
    pub n_elements: u32,
}

impl PatchForces {
    /// The forces, moment and pressure times `share` (a well's share of its Hertz solution,
    /// `crate::wells`); the patch's dimensions stay.
    fn scaled(mut self, share: f64) -> PatchForces {
        if share != 1.0 {
            self.fn_ *= share;
            self.fx *= share;
            self.fs *= share;
            self.mz *= share;
            self.p_max *= share;
        }
        self
    }
}

/// A solved patch with its geometry, in the side frame and in the track frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchResult {
    /// \[m\] lateral position of the patch reference point on the rail, in the rail-profile frame
    /// (toward the field side): the interpenetration-weighted centroid of the patch
    pub y_rail_profile: f64,
    /// \[m\] lateral position of the contact point on the wheel profile (S, toward the field side)
    pub y_wheel_profile: f64,
    /// \[m\] contact point on the rail in the track frame (x, y, z)
    pub point_track: [f64; 3],
    /// \[rad\] contact angle at the reference point, positive when the normal leans toward the
    /// flange; the forces are given in this plane
    pub contact_angle: f64,
    /// \[m\] the seed's rigid contact pair (theta_C = 90 deg, deepest interpenetration): lateral
    /// position on the rail profile
    pub rigid_pair_y_rail_profile: f64,
    /// \[rad\] contact angle at the rigid contact pair
    pub rigid_pair_contact_angle: f64,
    /// \[m\] largest interpenetration of the undeformed profiles (the seed's delta_0); for
    /// `halfspace` the elastic approach of the patch
    pub penetration: f64,
    /// \[m\] wheel radius at the contact point
    pub rolling_radius: f64,
    /// Creepages at the reference point (Kalker's convention, patch axes; spin in 1/m).
    pub creepages: Creepages,
    /// Forces in the patch axes.
    pub forces: PatchForces,
    /// \[N\] force on the wheel in the track frame (x, y, z)
    pub force_track: [f64; 3],
    /// \[N m\] spin moment on the wheel as a vector in the track frame: `forces.mz` about the
    /// normal at the reference point, so that with the force at `point_track` it is the
    /// patch's force system
    pub moment_track: [f64; 3],
    /// \[N\] force on the wheel in the wheelset frame (x forward, y along the axle to the left,
    /// z up, turned with the wheelset's yaw and roll): `R_TW^T F_track`
    pub force_wheelset: [f64; 3],
    /// \[rad\] largest travelling error (seed Fig. 10) among the patch's pairs
    pub travel_error: f64,
}

/// Statistics and totals of one wheel evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WheelSummary {
    /// Number of patches.
    pub n_patches: usize,
    /// \[N\] total force on the wheel in the track frame
    pub force_track: [f64; 3],
    /// Travelling statistics.
    pub travel: TravelStats,
    /// \[m\] vertical wheelset position used (after load iteration, if any)
    pub z: f64,
    /// Number of load iterations (0 when the position was prescribed).
    pub load_iterations: u32,
    /// \[N\] vertical force minus the prescribed load after the load iteration. Beyond the
    /// iteration's tolerance only where the force jumps across the load between two heights
    /// 1e-12 m apart, so that no height carries it: a zone appearing or vanishing at a coarse
    /// step, or a Hertz patch in deep conformal flange contact whose curvatures change abruptly
    /// with the height (docs/models/contact.md §8); the closer side is returned. Callers
    /// should report a residual above [`LOAD_RESIDUAL_NOTICE`] times the load.
    pub load_residual: f64,
}

/// \[-\] relative load residual (`WheelSummary::load_residual` over the load) above which a
/// prescribed-load evaluation did not carry its load and should say so.
pub const LOAD_RESIDUAL_NOTICE: f64 = 1e-4;

/// Reusable buffers for contact evaluations. Create once, pass to every evaluation; nothing is
/// allocated once the buffers have grown to the largest case.
#[derive(Default)]
pub struct ContactWorkspace {
    /// The isosceles pairs of the last travelling.
    pub pairs: Vec<IsoPair>,
    /// The zones of the last travelling.
    pub zones: Vec<Zone>,
    pairs_scratch: Vec<IsoPair>,
    broad: BroadScratch,
    /// Strips of the last STRIPES patch.
    pub strips: Vec<Strip>,
    local: Vec<Local>,
    exact: stripes::ExactScratch,
    /// Patch results of the last evaluation.
    pub patches: Vec<PatchResult>,
    halfspace: Option<HalfspaceScratch>,
    wells: WellScratch,
}

struct HalfspaceScratch {
    solver: HalfspaceSolver,
    gap: Vec<f64>,
}

impl ContactWorkspace {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }
}

/// A wheel/rail contact ready for evaluation: the pair and the options.
#[derive(Clone, Debug)]
pub struct WheelRailContact {
    /// The pair.
    pub pair: WheelRailPair,
    /// The options.
    pub opts: ContactOptions,
}

impl WheelRailContact {
    /// Combine a pair and options, checking the options.
    pub fn new(pair: WheelRailPair, opts: ContactOptions) -> Result<Self, ContactError> {
        opts.travel.validate()?;
        if opts.fastsim_nx < 2
            || opts.fastsim_nx > 1000
            || opts.fastsim_ny < 2
            || opts.fastsim_ny > 1000
        {
            return Err(ContactError::BadOption {
                key: "fastsim cells",
                value: format!("{} x {}", opts.fastsim_nx, opts.fastsim_ny),
                expected: "between 2 and 1000 cells each way".into(),
            });
        }
        for (name, (nx, ny)) in [
            ("halfspace cells", opts.halfspace_cells),
            ("exact cells", opts.exact_cells),
        ] {
            if !(2..=1024).contains(&nx) || !(2..=1024).contains(&ny) {
                return Err(ContactError::BadOption {
                    key: name,
                    value: format!("{nx} x {ny}"),
                    expected: "between 2 and 1024 cells each way".into(),
                });
            }
        }
        if let Some((key, value, expected)) = opts
            .polach
            .problem()
            .or_else(|| opts.falling_friction.problem())
        {
            return Err(ContactError::BadOption {
                key,
                value,
                expected: expected.into(),
            });
        }
        // The reference levels and the linear model take Coulomb friction (or none).
        if !opts.falling_friction.is_coulomb() {
            let refused = match opts.model {
                ContactModelKind::Linear => Some("the linear model, which has no friction"),
                ContactModelKind::Halfspace => Some("the half-space model, a reference level"),
                ContactModelKind::Stripes if opts.tangential == Tangential::Exact => {
                    Some("the exact tangential solution, a reference level")
                }
                _ => None,
            };
            if let Some(what) = refused {
                return Err(ContactError::BadOption {
                    key: "falling friction",
                    value: format!(
                        "A = {}, B = {} s/m with {what}",
                        opts.falling_friction.ratio, opts.falling_friction.decay
                    ),
                    expected: "Coulomb friction (A = 1 or B = 0), or the model polach, fastsim \
                               or stripes with a FASTSIM-type tangential solution"
                        .into(),
                });
            }
        }
        Ok(WheelRailContact { pair, opts })
    }

    /// Evaluate the contact of one wheel at a prescribed wheelset pose (track frame). Patches go
    /// to `ws.patches`; no contact gives no patches, which is not an error.
    pub fn evaluate(
        &self,
        side: Side,
        pose: &WheelsetPose,
        vel: &WheelsetVelocity,
        ws: &mut ContactWorkspace,
    ) -> Result<WheelSummary, ContactError> {
        self.evaluate_inner(side, pose, vel, None, ws)
    }

    /// [`evaluate`](Self::evaluate) with the warm start `warm` of this wheel (one per wheel, kept
    /// between evaluations): the travelling covers only windows around the previous contact
    /// where its certificate allows (`crate::warm`), with the same patches and forces as a cold
    /// evaluation to within the travelling's angle tolerance.
    pub fn evaluate_warm(
        &self,
        side: Side,
        pose: &WheelsetPose,
        vel: &WheelsetVelocity,
        warm: &mut WarmStart,
        ws: &mut ContactWorkspace,
    ) -> Result<WheelSummary, ContactError> {
        self.evaluate_inner(side, pose, vel, Some(warm), ws)
    }

    fn evaluate_inner(
        &self,
        side: Side,
        pose: &WheelsetPose,
        vel: &WheelsetVelocity,
        mut warm: Option<&mut WarmStart>,
        ws: &mut ContactWorkspace,
    ) -> Result<WheelSummary, ContactError> {
        let checked = pose.validate().and_then(|_| vel.validate()).and_then(|_| {
            let limit = self.pair.locus.tan_yaw_max;
            if pose.yaw.tan().abs() > limit {
                Err(ContactError::YawBeyondLocus {
                    yaw: pose.yaw,
                    limit: limit.atan(),
                })
            } else {
                Ok(())
            }
        });
        if let Err(e) = checked {
            if let Some(w) = warm.as_mut() {
                w.invalidate();
            }
            return Err(e);
        }
        let sp = pose.to_side(side);
        let sv = vel.to_side(side);
        let ctx = PoseCtx::new(&self.pair, &sp);
        let point_search =
            self.opts.hertz_search == HertzSearch::Point && self.opts.model.is_hertz();
        let mut found = None;
        if point_search {
            // (the travelling's memory would describe an older pose)
            let memory = warm.as_mut().map(|w| {
                w.invalidate_travel();
                &mut w.broad
            });
            let result = self.point_search(side, pose, &ctx, memory, ws);
            if let Some(w) = warm.as_mut() {
                match &result {
                    Ok(Some(s)) if s.warm => w.warm_count += 1,
                    // (`None`: left to the cold travelling below)
                    Ok(_) => w.cold_count += 1,
                    Err(_) => w.invalidate(),
                }
            }
            found = result?;
        }
        // the point search's pairs are its wells' exact minima, one per zone, with their shares
        let searched = found.is_some();
        let stats = match found {
            Some(stats) => stats,
            None => {
                // (a point-search model keeps no travelling memory: its fallback travels cold,
                // windowed, with or without a warm start)
                let warm = if point_search { None } else { warm };
                let stats = self
                    .travel_zones(&sp, &ctx, warm, ws)
                    .map_err(|()| self.no_overlap(side, pose))?;
                if self.opts.model.is_hertz() {
                    split_into_wells(&ws.pairs, &mut ws.zones, &mut ws.wells, false);
                }
                stats
            }
        };
        let kin = WheelKinematics::new(&ctx, sp.roll, &sv);
        // A constant creep coefficient is the wheel's (Wickens' model): its patches share it
        // in proportion to their normal forces, which needs their sum first.
        let wheel_fn = match self.opts.linear_creep {
            Some(_) if ws.zones.len() > 1 => {
                let mut sum = 0.0;
                for zone in &ws.zones {
                    let frame = patch_frame(&self.pair, &ctx, &ws.pairs, zone, !searched);
                    if frame.delta0 > self.opts.max_penetration {
                        // (reported by the loop below, as for every model)
                        continue;
                    }
                    let mat = &self.pair.material;
                    sum += zone.share
                        * hertz_from_approach(frame.a_curv, frame.b_curv, frame.delta0, mat)?.n;
                }
                sum
            }
            _ => 0.0,
        };
        ws.patches.clear();
        let mut total = [0.0; 3];
        for zi in 0..ws.zones.len() {
            let zone = ws.zones[zi];
            let frame = patch_frame(&self.pair, &ctx, &ws.pairs, &zone, !searched);
            if frame.delta0 > self.opts.max_penetration {
                return Err(ContactError::AbsurdPenetration {
                    side: side.name(),
                    found_mm: frame.delta0 * 1e3,
                    limit_mm: self.opts.max_penetration * 1e3,
                });
            }
            let creep = kin.creepages(frame.wheel_point, frame.t, frame.n);
            let input = PatchInput {
                pair: &self.pair,
                pairs: &ws.pairs,
                zone,
                frame,
                kin: &kin,
                creep,
                reference: reference_point(&ws.pairs, &zone),
                ctx,
            };
            let (forces, penetration) = match self.opts.model {
                ContactModelKind::Stripes => (
                    stripes::solve(
                        &input,
                        self.opts.stripes_variant,
                        self.opts.tangential,
                        &self.opts.falling_friction,
                        self.opts.fastsim_nx,
                        self.opts.bound,
                        self.opts.exact_cells,
                        &mut ws.strips,
                        &mut ws.local,
                        &mut ws.exact,
                        &mut ws.wells,
                    )?,
                    frame.delta0,
                ),
                ContactModelKind::Linear => (
                    self.solve_hertz(&input, HertzTangential::Linear { wheel_fn })?,
                    frame.delta0,
                ),
                ContactModelKind::Fastsim => (
                    self.solve_hertz(&input, HertzTangential::Fastsim)?,
                    frame.delta0,
                ),
                ContactModelKind::Polach => (
                    self.solve_hertz(&input, HertzTangential::Polach)?,
                    frame.delta0,
                ),
                ContactModelKind::Halfspace => {
                    let mut f =
                        solve_halfspace(&input, &self.opts, &mut ws.halfspace, &mut ws.exact)?;
                    // The half-space patch is planar: its plane is the reference point's
                    // (CONTACT's, D = 2), not the rigid pair's (until stop 34), which on a wide
                    // conformal patch leans by 0.01 rad (docs/models/contact.md §5).
                    (f.fn_, f.fs) =
                        from_plane_to_frame(f.fn_, f.fs, input.reference.1, frame.contact_angle);
                    (f, frame.delta0)
                }
            };
            // a well of a zone with several carries its share of its Hertz solution
            let forces = forces.scaled(zone.share);
            if forces.fn_ <= 0.0 {
                continue;
            }
            let r = self.result(
                side,
                pose,
                &frame,
                &kin,
                forces,
                penetration,
                &ws.pairs[zone.first..=zone.last],
                input.reference,
            );
            for k in 0..3 {
                total[k] += r.force_track[k];
            }
            ws.patches.push(r);
        }
        Ok(WheelSummary {
            n_patches: ws.patches.len(),
            force_track: total,
            travel: stats,
            z: pose.z,
            load_iterations: 0,
            load_residual: 0.0,
        })
    }

    /// The seed's travelling (warm-started where possible) and the zones of its pairs, in
    /// `ws.pairs` and `ws.zones`; `Err` when the profiles do not overlap laterally.
    fn travel_zones(
        &self,
        sp: &WheelsetPose,
        ctx: &PoseCtx,
        mut warm: Option<&mut WarmStart>,
        ws: &mut ContactWorkspace,
    ) -> Result<TravelStats, ()> {
        let mut stats = TravelStats::default();
        let warm_travelled = warm.as_mut().is_some_and(|w| {
            w.travel(
                &self.pair,
                ctx,
                &self.opts.travel,
                &mut ws.pairs,
                &mut stats,
            )
        });
        if !warm_travelled {
            // Without a warm start, only windows around the broad phase's candidates are
            // travelled where that can be vouched for; a warm start needs the whole profile's
            // bounds.
            let windowed = warm.is_none()
                && point::travel_windows(
                    &self.pair,
                    ctx,
                    &self.opts.travel,
                    &mut ws.broad,
                    &mut ws.pairs,
                    &mut stats,
                );
            if !windowed {
                stats = travel(&self.pair, sp, &self.opts.travel, &mut ws.pairs);
            }
            if let Some(w) = warm {
                w.store_cold(&self.pair, ctx, &ws.pairs);
            }
        }
        stats.warm = warm_travelled;
        if !warm_travelled && ws.pairs.len() < 3 {
            return Err(());
        }
        self.zones(&ws.pairs, &mut ws.zones, &mut ws.wells);
        if self.opts.min_zone_pairs > 0
            && refine_narrow_zones(
                &self.pair,
                sp,
                &self.opts.travel,
                self.opts.min_zone_pairs,
                self.opts.model == ContactModelKind::Stripes,
                &mut ws.pairs,
                &ws.zones,
                &mut ws.pairs_scratch,
                &mut stats,
            )
        {
            self.zones(&ws.pairs, &mut ws.zones, &mut ws.wells);
        }
        Ok(stats)
    }

    /// The zones of travelled pairs: STRIPES solves every well of a run as a patch with its
    /// share (`crate::wells`, docs/models/contact.md §4.1) and the half-space model each such
    /// patch's basins whole, in one plane (§4); for the Hertz models the runs as `find_zones`
    /// splits them, cut into wells afterwards.
    fn zones(&self, pairs: &[IsoPair], zones: &mut Vec<Zone>, wells: &mut WellScratch) {
        if matches!(
            self.opts.model,
            ContactModelKind::Stripes | ContactModelKind::Halfspace
        ) {
            split_into_wells(pairs, zones, wells, true);
        } else {
            find_zones(
                pairs,
                self.opts.split_angle,
                self.opts.split_depth_ratio,
                zones,
            );
        }
    }

    /// The single-point search of the Hertz models (`crate::point`): one pair per zone in
    /// `ws.pairs`, one-pair zones in `ws.zones`; `None` where it leaves the pose to the
    /// travelling.
    fn point_search(
        &self,
        side: Side,
        pose: &WheelsetPose,
        ctx: &PoseCtx,
        memory: Option<&mut BroadMemory>,
        ws: &mut ContactWorkspace,
    ) -> Result<Option<TravelStats>, ContactError> {
        // The profiles must overlap laterally, as for the travelling.
        let y_tip = locus(&self.pair, ctx, self.pair.wheel_s_tip).p[1];
        let y_end = locus(&self.pair, ctx, self.pair.wheel.length()).p[1];
        let (r0, r1) = self.pair.rail.y_range();
        if y_end.min(r1) - y_tip.max(r0) <= 0.0 {
            return Err(self.no_overlap(side, pose));
        }
        Ok(point::search(
            &self.pair,
            ctx,
            &self.opts.travel,
            &mut ws.broad,
            memory,
            &mut ws.pairs,
            &mut ws.zones,
        ))
    }

    /// The error of a pose where the wheel and rail profiles do not face each other, with
    /// their lateral spans in the side frame (where the wheel's flange tip and field end lie,
    /// where the rail profile lies), so that a wrong gauge or profile origin shows.
    fn no_overlap(&self, side: Side, pose: &WheelsetPose) -> ContactError {
        let ctx = PoseCtx::new(&self.pair, &pose.to_side(side));
        let y_tip = locus(&self.pair, &ctx, self.pair.wheel_s_tip).p[1];
        let y_end = locus(&self.pair, &ctx, self.pair.wheel.length()).p[1];
        let (r0, r1) = self.pair.rail.y_range();
        ContactError::NoOverlap {
            side: side.name(),
            y_mm: pose.y * 1e3,
            wheel_mm: [y_tip * 1e3, y_end * 1e3],
            rail_mm: [r0 * 1e3, r1 * 1e3],
        }
    }

    /// Evaluate with a prescribed vertical load: the wheelset height `pose.z` is iterated
    /// (safeguarded secant) until the vertical force of this wheel equals `fz` (the wheel load,
    /// positive up on the wheel) to `rel_tol`. The converged pose height is in the summary.
    pub fn evaluate_with_load(
        &self,
        side: Side,
        pose: &WheelsetPose,
        vel: &WheelsetVelocity,
        fz: f64,
        rel_tol: f64,
        ws: &mut ContactWorkspace,
    ) -> Result<WheelSummary, ContactError> {
        crate::error::finite("vertical load", fz)?;
        if fz <= 0.0 {
            return Err(ContactError::OutOfRange {
                what: "vertical load [N]",
                value: fz,
                expected: "a positive wheel load",
            });
        }
        pose.validate()?;
        vel.validate()?;
        // First touch: the height at which the deepest pair just touches, from the pairs' gaps
        // projected on the vertical. Deep interpenetration (a flange driven into the rail) can
        // hide pairs, so the estimate is repeated from the lifted height until nothing
        // interpenetrates any more, then the wheel is lowered onto the rail.
        let mut z_touch = pose.z;
        let mut found = false;
        let mut prev_dz = 0.0;
        let mut z_cycle = f64::NEG_INFINITY;
        for _ in 0..20 {
            let mut q = *pose;
            q.z = z_touch;
            travel(
                &self.pair,
                &q.to_side(side),
                &self.opts.travel,
                &mut ws.pairs,
            );
            let mut dz = f64::INFINITY;
            for p in &ws.pairs {
                if p.n[1] > 0.2 {
                    dz = dz.min(p.gap / p.n[1]);
                }
            }
            if !dz.is_finite() {
                break;
            }
            // Far from contact the pairs are coarse and overestimate the distance, so the
            // estimate is repeated until it no longer moves the wheel.
            z_touch -= dz;
            // Converged; or alternating at the sub-micrometre level, where the sampling of the
            // pairs near the closest point flips between two patterns: either height is the
            // first touch to within |dz|.
            if dz.abs() < 1e-9 || (dz.abs() < 1e-6 && dz * prev_dz < 0.0) {
                found = true;
                break;
            }
            if dz.abs() < 5e-5 {
                z_cycle = z_cycle.max(z_touch);
            }
            prev_dz = dz;
        }
        if !found && z_cycle.is_finite() {
            // A limit cycle of the estimate (the closest point between coarse pairs on a steep
            // flange): start from the highest height it visited, where the wheel touches least.
            z_touch = z_cycle;
            found = true;
        }
        if !found {
            return Err(self.no_overlap(side, pose));
        }
        // Bracket: F(z_touch) = 0; go down until the load is exceeded.
        let f_at =
            |z: f64, ws: &mut ContactWorkspace| -> Result<(f64, WheelSummary), ContactError> {
                let mut q = *pose;
                q.z = z;
                let s = self.evaluate(side, &q, vel, ws)?;
                Ok((s.force_track[2], s))
            };
        let mut z_hi = z_touch; // force 0
        let mut f_hi = 0.0;
        let mut dz = 2e-5;
        let (mut z_lo, mut f_lo);
        let mut it = 0u32;
        loop {
            z_lo = z_touch - dz;
            f_lo = f_at(z_lo, ws)?.0;
            it += 1;
            if f_lo >= fz {
                break;
            }
            z_hi = z_lo;
            f_hi = f_lo;
            // (the last try is just inside the limit, where the interpenetration, at most the
            // lowering, is still accepted: doubling past it skipped the lowerings between half
            // the limit and the limit, and the message gave twice the last one)
            let last = LAST_LOWERING * self.opts.max_penetration;
            if dz >= last {
                return Err(ContactError::LoadNotReached {
                    side: side.name(),
                    target_n: fz,
                    reason: format!(
                        "the vertical force is only {:.1} N at {:.3} mm below first touch, the \
                         largest interpenetration allowed",
                        f_lo,
                        dz * 1e3
                    ),
                });
            }
            dz = (2.0 * dz).min(last);
        }
        // Illinois-safeguarded regula falsi on z, with the force ~ delta^1.5 linearised by
        // working on F^(2/3).
        let g = |f: f64| f.max(0.0).powf(2.0 / 3.0) - fz.powf(2.0 / 3.0);
        let (mut ga, mut gb) = (g(f_hi), g(f_lo));
        let (mut za, mut zb) = (z_hi, z_lo);
        let mut side_kept = 0i32;
        let mut best = (f64::INFINITY, z_lo);
        let mut converged = false;
        for _ in 0..60 {
            let z = zb - gb * (zb - za) / (gb - ga);
            let (f, _) = f_at(z, ws)?;
            it += 1;
            if (f - fz).abs() < best.0 {
                best = ((f - fz).abs(), z);
            }
            if (f - fz).abs() <= rel_tol * fz {
                converged = true;
                break;
            }
            let gz = g(f);
            if gz * gb < 0.0 {
                za = zb;
                ga = gb;
                side_kept = 0;
            } else {
                side_kept += 1;
                if side_kept >= 1 {
                    ga *= 0.5;
                }
            }
            zb = z;
            gb = gz;
            if (zb - za).abs() < 1e-12 {
                // The bracket has collapsed on a jump of the force: at this travelling step a
                // zone appears or vanishes between two heights 1e-12 m apart. The closer side
                // is taken and the residual reported.
                break;
            }
        }
        let (res, z) = best;
        if !converged && (zb - za).abs() >= 1e-12 {
            return Err(ContactError::LoadNotReached {
                side: side.name(),
                target_n: fz,
                reason: format!("no convergence in {it} iterations, closest {res:.1} N off"),
            });
        }
        let (_, mut s) = f_at(z, ws)?;
        s.z = z;
        s.load_iterations = it;
        s.load_residual = s.force_track[2] - fz;
        Ok(s)
    }

    fn solve_hertz(
        &self,
        input: &PatchInput<'_>,
        kind: HertzTangential,
    ) -> Result<PatchForces, ContactError> {
        let fr = &input.frame;
        let mat = &self.pair.material;
        let mu = self.pair.friction.at(fr.contact_angle);
        let hz = hertz_from_approach(fr.a_curv, fr.b_curv, fr.delta0, mat)?;
        let tang = if let HertzTangential::Linear { wheel_fn } = kind {
            match self.opts.linear_creep {
                // Wickens' linear model: Fx = -f xi, Fy = -f eta, no spin, with f the wheel's,
                // shared by its patches in proportion to their normal forces (the share of a
                // well is applied by the caller, as to its normal force).
                Some(f) => {
                    let w = if wheel_fn > 0.0 { hz.n / wheel_fn } else { 1.0 };
                    TangentialForces {
                        fx: -f * w * input.creep.xi,
                        fy: -f * w * input.creep.eta,
                        mz: 0.0,
                        adhesion_fraction: 1.0,
                    }
                }
                None => linear_kalker(hz.a, hz.b, &input.creep, mat)?,
            }
        } else if kind == HertzTangential::Polach {
            polach(
                hz.a,
                hz.b,
                hz.n,
                &input.creep,
                input.kin.v_ref,
                &self.opts.polach.at(mu, &self.opts.falling_friction),
                mat,
            )?
        } else {
            // friction falling with Polach's slip velocity of the ellipse (`FallingFriction`)
            let falling = &self.opts.falling_friction;
            let mu = if falling.is_coulomb() {
                mu
            } else {
                let w = spin_corrected_creepage(&input.creep, hz.a).0 * input.kin.v_ref;
                mu * falling.factor(w)
            };
            let flex = blended_flexibilities(hz.a, hz.b, hz.n, mu, &input.creep, mat)?;
            fastsim_ellipse(
                hz.a,
                hz.b,
                hz.n,
                &input.creep,
                &flex,
                mu,
                self.opts.bound,
                self.opts.fastsim_ny,
                self.opts.fastsim_nx,
            )?
        };
        Ok(PatchForces {
            fn_: hz.n,
            fx: tang.fx,
            fs: tang.fy,
            mz: tang.mz,
            p_max: hz.p0,
            length: 2.0 * hz.a,
            width: 2.0 * hz.b,
            area: std::f64::consts::PI * hz.a * hz.b,
            adhesion_fraction: tang.adhesion_fraction,
            n_elements: 1,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn result(
        &self,
        side: Side,
        pose: &WheelsetPose,
        fr: &PatchFrame,
        kin: &WheelKinematics,
        f: PatchForces,
        penetration: f64,
        zone_pairs: &[IsoPair],
        (rp, angle): (IsoPair, f64),
    ) -> PatchResult {
        let sg = side.sign();
        // Force on the wheel in the side frame: x, then s and n in the (y, z) plane.
        let fy = f.fs * fr.t[0] + f.fn_ * fr.n[0];
        let fzv = f.fs * fr.t[1] + f.fn_ * fr.n[1];
        let mut err: f64 = 0.0;
        for p in zone_pairs {
            err = err.max(p.travel_error);
        }
        // Report in the frame of the patch reference point (see `reference_point`): the same
        // force vector, decomposed along the reference normal and tangent.
        let (sa, ca) = angle.sin_cos();
        let n_ref = [-sa, ca];
        let t_ref = [ca, sa];
        let mut fr_ref = f;
        fr_ref.fn_ = fy * n_ref[0] + fzv * n_ref[1];
        fr_ref.fs = fy * t_ref[0] + fzv * t_ref[1];
        // Spin moment about the reference point, offset (dx along x, dl along t) from the rigid
        // pair. (dx, the difference of the yawed leads, was left out: the flank patch of a
        // yawed two-point contact reported -14.8 N·m where +20.6 N·m is right.)
        let dl = (rp.b[0] - fr.rail_point[0]) * fr.t[0] + (rp.b[1] - fr.rail_point[1]) * fr.t[1];
        let dx = rp.x - fr.wheel_point[0];
        fr_ref.mz = spin_moment_moved(f.mz, f.fx, f.fs, dx, dl);
        // The spin moment vector (pseudo-vector) about the reference normal, so that with the
        // force at the reference point (`point_track`) it is the patch's force system; the
        // mirror flips its x and z components.
        let m_side = [0.0, fr_ref.mz * n_ref[0], fr_ref.mz * n_ref[1]];
        // and the creepages there (the patch's own solution used the rigid pair's, or each
        // strip's; before stop 24 the rigid pair's were reported)
        let creep = kin.creepages([rp.x, rp.a[0], rp.a[1]], t_ref, n_ref);
        PatchResult {
            y_rail_profile: self.pair.rail_profile_y(rp.b[0], rp.b[1]),
            y_wheel_profile: self.pair.wheel.eval(rp.s_w).p[0],
            point_track: [rp.x, sg * rp.b[0], rp.b[1]],
            contact_angle: angle,
            rigid_pair_y_rail_profile: self.pair.rail_profile_y(fr.rail_point[0], fr.rail_point[1]),
            rigid_pair_contact_angle: fr.contact_angle,
            penetration,
            rolling_radius: rp.rho,
            creepages: creep,
            forces: fr_ref,
            force_track: [f.fx, sg * fy, fzv],
            force_wheelset: pose.track_to_wheelset([f.fx, sg * fy, fzv]),
            moment_track: [sg * m_side[0], m_side[1], sg * m_side[2]],
            travel_error: err,
        }
    }
}

/// Half-space reference: the patch's undeformed gap on a grid in the patch plane, the exact
/// elastic normal solution for the patch's penetration, and FaStrip or FASTSIM per grid row
/// with the row's load as a semi-ellipse and the Kalker coefficients and flexibilities of the
/// row's own ellipse (or Kalker's exact tangential solution on the grid).
fn solve_halfspace(
    input: &PatchInput<'_>,
    opts: &ContactOptions,
    scratch: &mut Option<HalfspaceScratch>,
    exact: &mut stripes::ExactScratch,
) -> Result<PatchForces, ContactError> {
    let fr = &input.frame;
    let pairs = input.pairs;
    let (lo, hi) = input.pair_range();
    let l_of = |i: usize| fr.lateral(&pairs[i]);
    // Walk a cursor over the pairs to the one before lateral coordinate l; returns the pair index
    // and the interpolation fraction toward the next pair.
    let bracket = |j: &mut usize, l: f64| -> (usize, f64) {
        while *j + 1 < hi && l_of(*j + 1) < l {
            *j += 1;
        }
        let (la, lb) = (l_of(*j), l_of((*j + 1).min(hi)));
        let f = if (lb - la).abs() > 1e-15 {
            ((l - la) / (lb - la)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (*j, f)
    };
    let d_of = |i: usize| fr.normal_interpenetration(&pairs[i]);
    // The interpenetration at lateral coordinate l between pairs j and j + 1: the mean of the
    // parabolas through (j - 1, j, j + 1) and (j, j + 1, j + 2), the third-order scheme of the
    // STRIPES strips (linear where neither exists). Linear interpolation inscribed a roof with a
    // kink at every pair, under which the half-space pressure peaked: p_max 13.5 % above Hertz
    // on two 0.3 m circles at the default 1 mm step, up to 30 % above CONTACT on the benchmark's
    // flange cases.
    let last_pair = pairs.len() - 1;
    let parabola = |i: usize, l: f64| -> Option<f64> {
        let (l0, l1, l2) = (l_of(i), l_of(i + 1), l_of(i + 2));
        if !(l1 - l0 > 1e-12 && l2 - l1 > 1e-12) {
            return None;
        }
        let (d0, d1, d2) = (d_of(i), d_of(i + 1), d_of(i + 2));
        Some(
            d0 * (l - l1) * (l - l2) / ((l0 - l1) * (l0 - l2))
                + d1 * (l - l0) * (l - l2) / ((l1 - l0) * (l1 - l2))
                + d2 * (l - l0) * (l - l1) / ((l2 - l0) * (l2 - l1)),
        )
    };
    let d_at = |j: usize, f: f64, l: f64| -> f64 {
        let k = (j + 1).min(last_pair);
        let linear = d_of(j) + f * (d_of(k) - d_of(j));
        if k == j {
            return linear;
        }
        let left = if j > 0 { parabola(j - 1, l) } else { None };
        let right = if k < last_pair { parabola(j, l) } else { None };
        match (left, right) {
            (Some(a), Some(b)) => 0.5 * (a + b),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => linear,
        }
    };
    // Lateral extent: the interpenetration zone, its edges the zeros of the interpolated
    // interpenetration between the zone's end pair `i` and the pair beyond it, `j`.
    let edge = |i: usize, j: usize| {
        let (di, dj) = (d_of(i), d_of(j));
        let (li, lj) = (l_of(i), l_of(j));
        if !(di > 0.0 && dj <= 0.0) {
            return lj;
        }
        let linear = li + (lj - li) * di / (di - dj);
        let jl = i.min(j);
        let (la, lb) = (l_of(jl), l_of(jl + 1));
        if jl + 1 != i.max(j) || lb - la <= 1e-12 {
            return linear;
        }
        // (the interpolant equals the pairs' values at its ends: a sign change to bisect)
        let at = |l: f64| d_at(jl, ((l - la) / (lb - la)).clamp(0.0, 1.0), l);
        let (mut inside, mut outside) = (li, lj);
        for _ in 0..40 {
            let mid = 0.5 * (inside + outside);
            if at(mid) > 0.0 {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        0.5 * (inside + outside)
    };
    let l_min = edge(input.zone.first, lo);
    let l_max = edge(input.zone.last, hi);
    // Longitudinal extent from the interpenetration half-lengths at the pairs and between them.
    let mut x_min = f64::INFINITY;
    let mut x_max = f64::NEG_INFINITY;
    for i in input.zone.first..=input.zone.last {
        let p = &pairs[i];
        let a = longitudinal_curvature(p.rho, p.rho_slope);
        let xc = p.x - fr.wheel_point[0];
        let mut d = d_of(i);
        if i < input.zone.last {
            let mid = 0.5 * (l_of(i) + l_of(i + 1));
            d = d.max(d_at(i, 0.5, mid));
        }
        let half = (d.max(0.0) / a).sqrt();
        x_min = x_min.min(xc - half);
        x_max = x_max.max(xc + half);
    }
    let (nx, ny) = opts.halfspace_cells;
    let width = (l_max - l_min).max(1e-7);
    let length = (x_max - x_min).max(1e-7);
    let dx = length * 1.04 / nx as f64;
    let dy = width * 1.04 / ny as f64;
    let grid = Grid {
        nx,
        ny,
        dx,
        dy,
        x0: 0.5 * (x_min + x_max) - 0.5 * (nx as f64 - 1.0) * dx,
        y0: 0.5 * (l_min + l_max) - 0.5 * (ny as f64 - 1.0) * dy,
    };
    let needs_new = match scratch {
        Some(s) => *s.solver.grid() != grid,
        None => true,
    };
    if needs_new {
        *scratch = Some(HalfspaceScratch {
            solver: HalfspaceSolver::new(grid, &input.pair.material)?,
            gap: vec![0.0; nx * ny],
        });
    }
    let sc = scratch.as_mut().expect("scratch was just set");
    // Gap of each cell: the strip's gap below the deepest point plus the longitudinal parabola;
    // the interpenetration interpolated between the pairs as above, the lead and the curvature
    // linearly.
    let mut cursor = lo;
    for iy in 0..ny {
        let l = grid.y0 + iy as f64 * dy;
        let (j, f) = bracket(&mut cursor, l);
        let pa = &pairs[j];
        let pb = &pairs[(j + 1).min(hi)];
        let d = if (j + 1).min(hi) == j {
            d_of(j)
        } else {
            d_at(j, f, l.clamp(l_of(j), l_of(j + 1)))
        };
        let xc = pa.x + f * (pb.x - pa.x) - fr.wheel_point[0];
        let a = longitudinal_curvature(
            pa.rho + f * (pb.rho - pa.rho),
            pa.rho_slope + f * (pb.rho_slope - pa.rho_slope),
        );
        for ix in 0..nx {
            let x = grid.x0 + ix as f64 * dx;
            sc.gap[ix + nx * iy] = fr.delta0 - d + a * (x - xc) * (x - xc);
        }
    }
    let sol = sc.solver.solve_approach(&sc.gap, fr.delta0, 1e-9, 500)?;
    let pr = sc.solver.pressure();
    let mut f = PatchForces {
        fn_: sol.force,
        p_max: sol.p_max,
        area: sol.n_contact as f64 * dx * dy,
        n_elements: sol.n_contact as u32,
        ..Default::default()
    };
    // Extents of the loaded cells.
    {
        let mut ymin = f64::INFINITY;
        let mut ymax = f64::NEG_INFINITY;
        let mut xmn = f64::INFINITY;
        let mut xmx = f64::NEG_INFINITY;
        for iy in 0..ny {
            for ix in 0..nx {
                if pr[ix + nx * iy] > 0.0 {
                    let x = grid.x0 + ix as f64 * dx;
                    let y = grid.y0 + iy as f64 * dy;
                    ymin = ymin.min(y);
                    ymax = ymax.max(y);
                    xmn = xmn.min(x);
                    xmx = xmx.max(x);
                }
            }
        }
        if !ymin.is_finite() {
            return Ok(PatchForces::default());
        }
        f.width = ymax - ymin + dy;
        f.length = xmx - xmn + dx;
    }
    if opts.tangential == Tangential::Exact {
        // Kalker's exact solution on the half-space grid itself, with its pressure and, for a
        // varying friction, each row's coefficient at its pair's normal.
        exact.prepare_with(grid, &input.pair.material, pr)?;
        if !input.pair.friction.is_constant() {
            let mut cursor = lo;
            for iy in 0..ny {
                let (j, t) = bracket(&mut cursor, grid.y0 + iy as f64 * dy);
                let p = crate::patch::lerp_pair(&pairs[j], &pairs[(j + 1).min(hi)], t);
                exact.mu_row.push(input.pair.friction.at_normal(p.n));
            }
        }
        stripes::solve_exact(input, grid, exact, &mut f)?;
        return Ok(f);
    }
    // FaStrip or FASTSIM per row, each row with the Kalker coefficients and flexibilities of its
    // own ellipse (`stripes::StripEllipse`, as the strips of `stripes`): the Hertz ellipse of
    // the row's relative curvatures (interpolated between its two pairs) at the patch's
    // approach. The patch's area- and aspect-preserving equivalent ellipse stands in where that
    // ellipse is degenerate.
    let r = (f.area / std::f64::consts::PI).sqrt();
    let source = stripes::EllipseSource {
        delta0: fr.delta0,
        equivalent: (
            r * (f.length / f.width).sqrt(),
            r * (f.width / f.length).sqrt(),
            f.fn_,
        ),
        mu: input.pair.friction.at(fr.contact_angle),
        mat: &input.pair.material,
        kalker: &input.pair.kalker,
    };
    // The rows' spin slip is split about CONTACT's reference point (the d^(5/2) centroid, where
    // the exact level's planar creepages are taken), `l_ref` across from the frame's point: FaStrip's
    // and FASTSIM's spin calibrations hold for a lateral coordinate from the ellipse's centre,
    // and a zone's deepest pair can lie at one end of a wide patch (docs/models/contact.md §6).
    let l_ref = fr.lateral(&input.reference.0);
    let mut ellipse: Option<stripes::StripEllipse> = None;
    let mut cursor = lo;
    let mut n_adh = 0;
    let mut n_cells = 0;
    for iy in 0..ny {
        let row = &pr[nx * iy..nx * (iy + 1)];
        let q: f64 = row.iter().sum::<f64>() * dx;
        if q <= 0.0 {
            continue;
        }
        let first = row.iter().position(|&p| p > 0.0).unwrap_or(0);
        let last = row.iter().rposition(|&p| p > 0.0).unwrap_or(nx - 1);
        let x_a = grid.x0 + (first as f64 - 0.5) * dx;
        let x_b = grid.x0 + (last as f64 + 0.5) * dx;
        let hl = 0.5 * (x_b - x_a);
        let xc = 0.5 * (x_a + x_b);
        let l = grid.y0 + iy as f64 * dy;
        let (j, fr_) = bracket(&mut cursor, l);
        let k = (j + 1).min(hi);
        let p = crate::patch::lerp_pair(&pairs[j], &pairs[k], fr_);
        let creep = input.kin.creepages([p.x, p.a[0], p.a[1]], fr.t, p.n);
        // the row's curvatures, as a strip's (`stripes::solve`)
        let a_long = longitudinal_curvature(p.rho, p.rho_slope);
        let kw_j = crate::geometry::locus_curvature_at(pairs, j, input.ctx.yawed);
        let kw_k = crate::geometry::locus_curvature_at(pairs, k, input.ctx.yawed);
        let kw = kw_j + fr_ * (kw_k - kw_j);
        let b = (0.5 * (kw - p.kappa_r)).max(crate::patch::B_MIN);
        let e = source.ellipse(&mut ellipse, a_long, b, || hertz_coeffs_fast(a_long, b))?;
        // The row is solved about the locus point where its creepages are taken, `lead` ahead of
        // the reference point (solved about the reference point, the spin term phi x counted the
        // yawed locus' lead twice, as STRIPES' strips once did); the moment is
        // carried back.
        let lead = p.x - fr.wheel_point[0];
        let st = e.solve(
            opts.tangential,
            opts.bound,
            l - l_ref,
            dy,
            xc - lead,
            hl,
            q,
            &creep,
            input.pair.friction.at_normal(p.n),
            opts.fastsim_nx,
        );
        f.fx += st.fx;
        f.fs += st.fy;
        // (the moment already holds the lever l - l_ref of the row's longitudinal force; the rest
        // of the lever, l_ref, carries it to the frame's point)
        f.mz += st.mz + lead * st.fy - l_ref * st.fx;
        n_adh += st.n_adhesion;
        n_cells += st.n_cells;
    }
    f.adhesion_fraction = if n_cells > 0 {
        n_adh as f64 / n_cells as f64
    } else {
        0.0
    };
    let _ = sol.approach;
    Ok(f)
}

#[cfg(test)]
mod spin_moment_at_reference_tests {
    use super::*;
    use crate::contact_format::manchester_benchmark_pair;
    use crate::pose::{cross, dot3};

    /// A yawed wheelset in flange contact: each patch's reported moment about its normal
    /// (`moment_track`, the spin moment `forces.mz` along the reference normal) must be the
    /// moment of the patch's own force system moved from the rigid contact pair, where the model
    /// solved it, to the reported point `point_track`: `M_ref = M_rigid + (r_rigid - r_ref) × F`
    /// (rigid-body statics), taken about the rigid pair's normal as `patch::spin_moment_moved`
    /// documents. The rigid pair, its frame and the model's local solution are recomputed here
    /// from the evaluation's travelled pairs and zones; the reported force must equal the local
    /// one (the same patch), and the lead offset `dx` must matter (yaw), so that reporting the
    /// plain moment `f.mz`, or the moment moved without `-dx·Fs`, fails.
    #[test]
    fn a_yawed_flange_patch_reports_its_spin_moment_moved_to_the_reference_point() {
        let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
        let vel = WheelsetVelocity {
            vx: 30.0,
            vy: 0.01,
            spin: 30.0 / 0.46,
            ..Default::default()
        };
        for model in [ContactModelKind::Fastsim, ContactModelKind::Stripes] {
            let opts = ContactOptions {
                model,
                hertz_search: HertzSearch::Travel,
                ..Default::default()
            };
            let contact =
                WheelRailContact::new(manchester_benchmark_pair(&root).unwrap(), opts).unwrap();
            // the left wheel, and the right wheel in the mirrored pose and velocities (the same
            // patch with the mirror's signs)
            for side in [Side::Left, Side::Right] {
                let sg = side.sign();
                let pose = WheelsetPose {
                    y: 6.42e-3,
                    z: 0.385e-3,
                    roll: 0.78e-3,
                    yaw: 12e-3,
                }
                .to_side(side);
                let vel = vel.to_side(side);
                let mut ws = ContactWorkspace::new();
                contact.evaluate(side, &pose, &vel, &mut ws).unwrap();
                // Recompute every zone's local solution as the evaluation did.
                let sp = pose.to_side(side);
                let ctx = PoseCtx::new(&contact.pair, &sp);
                let kin = WheelKinematics::new(&ctx, sp.roll, &vel.to_side(side));
                let mut locals = Vec::new();
                let (mut strips, mut local, mut exact, mut wells) = (
                    Vec::new(),
                    Vec::new(),
                    stripes::ExactScratch::default(),
                    WellScratch::default(),
                );
                for &zone in &ws.zones {
                    let frame = patch_frame(&contact.pair, &ctx, &ws.pairs, &zone, true);
                    let input = PatchInput {
                        pair: &contact.pair,
                        pairs: &ws.pairs,
                        zone,
                        frame,
                        kin: &kin,
                        creep: kin.creepages(frame.wheel_point, frame.t, frame.n),
                        reference: reference_point(&ws.pairs, &zone),
                        ctx,
                    };
                    let f = match model {
                        ContactModelKind::Fastsim => {
                            contact.solve_hertz(&input, HertzTangential::Fastsim)
                        }
                        _ => stripes::solve(
                            &input,
                            opts.stripes_variant,
                            opts.tangential,
                            &opts.falling_friction,
                            opts.fastsim_nx,
                            opts.bound,
                            opts.exact_cells,
                            &mut strips,
                            &mut local,
                            &mut exact,
                            &mut wells,
                        ),
                    }
                    .unwrap()
                    .scaled(zone.share);
                    if f.fn_ > 0.0 {
                        locals.push((frame, f));
                    }
                }
                assert_eq!(locals.len(), ws.patches.len(), "{}", model.name());
                let mut flange = 0;
                for (p, (fr, f)) in ws.patches.iter().zip(&locals) {
                    // the local force in the track frame (side frame mirrored for the right wheel)
                    let fy = f.fs * fr.t[0] + f.fn_ * fr.n[0];
                    let fz = f.fs * fr.t[1] + f.fn_ * fr.n[1];
                    let force = [f.fx, sg * fy, fz];
                    let scale_f = force.iter().map(|v| v.abs()).fold(0.0, f64::max);
                    for k in 0..3 {
                        assert!(
                            (p.force_track[k] - force[k]).abs() <= 1e-12 * scale_f,
                            "{}: not the same patch: {:?} vs {force:?}",
                            model.name(),
                            p.force_track
                        );
                    }
                    // rigid pair (wheel point's lead, rail point) and its normal, track frame
                    let r_rigid = [fr.wheel_point[0], sg * fr.rail_point[0], fr.rail_point[1]];
                    let n_rigid = [0.0, sg * fr.n[0], fr.n[1]];
                    // the local spin moment as a pseudo-vector in the track frame
                    let m_rigid = [0.0, f.mz * fr.n[0], sg * f.mz * fr.n[1]];
                    let d = std::array::from_fn(|k| r_rigid[k] - p.point_track[k]);
                    let moved = cross(d, p.force_track);
                    let expected = dot3(m_rigid, n_rigid) + dot3(moved, n_rigid);
                    // the reported moment about the reference normal
                    let (sa, ca) = p.contact_angle.sin_cos();
                    let n_ref = [0.0, -sg * sa, ca];
                    let got = dot3(p.moment_track, n_ref);
                    // the lead offset's share (-dx Fs) of the moved moment
                    let lead = dot3(cross([d[0], 0.0, 0.0], p.force_track), n_rigid);
                    let t_rigid = [0.0, sg * fr.t[0], fr.t[1]];
                    eprintln!(
                        "{} {}: angle {:.3} rad (rigid pair {:.3}), dx {:.3} mm, dl {:.3} mm: \
                     reported {got:.4} N m, moved {expected:.4} N m, local {:.4} N m, \
                     lead term {lead:.4} N m",
                        model.name(),
                        side.name(),
                        p.contact_angle,
                        fr.contact_angle,
                        -d[0] * 1e3,
                        -dot3(d, t_rigid) * 1e3,
                        sg * f.mz
                    );
                    let tol = 1e-9 * (f.mz.abs() + scale_f * 1e-3);
                    assert!(
                        (got - expected).abs() <= tol,
                        "{}: reported {got} N m about the reference normal, {expected} N m moved",
                        model.name()
                    );
                    if fr.contact_angle > 0.5 {
                        flange += 1;
                        assert!(lead.abs() > 1e3 * tol, "{}: lead term {lead}", model.name());
                    }
                }
                assert!(flange > 0, "{}: no flange patch", model.name());
            }
        }
    }
}

#[cfg(test)]
mod linear_creep_tests {
    use super::*;
    use crate::contact_format::manchester_benchmark_pair;

    /// A constant creep coefficient is the wheel's, shared by its patches in proportion to their
    /// normal forces. S1002 on UIC60, centred, at 8.9 kN has two patches (the tread and a small
    /// one 11 mm toward the field side, about 600 N). Between two spins Ω1 and Ω2 each patch's
    /// longitudinal creepage changes by −ρ_i (Ω2 − Ω1)/V, so the wheel's longitudinal force
    /// changes by f (Ω2 − Ω1)/V Σ w_i ρ_i with shares w_i: divided by f (Ω2 − Ω1)/V that is a
    /// mean rolling radius, between the patches' radii, when the shares sum to one (twice it when
    /// each patch took the whole f, as before).
    #[test]
    fn a_constant_creep_coefficient_is_shared_by_the_patches() {
        let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
        let f = 1e7;
        let opts = ContactOptions {
            model: ContactModelKind::Linear,
            linear_creep: Some(f),
            ..Default::default()
        };
        let c = WheelRailContact::new(manchester_benchmark_pair(&root).unwrap(), opts).unwrap();
        let mut ws = ContactWorkspace::new();
        let pose = WheelsetPose::default();
        let v = 20.0;
        let spins = [v / 0.46, v / 0.46 * (1.0 + 1e-4)];
        let mut fx = [0.0; 2];
        let mut radii = Vec::new();
        for (k, spin) in spins.into_iter().enumerate() {
            let vel = WheelsetVelocity {
                vx: v,
                spin,
                ..Default::default()
            };
            let s = c
                .evaluate_with_load(Side::Left, &pose, &vel, 8.9e3, 1e-9, &mut ws)
                .unwrap();
            assert_eq!(s.n_patches, 2);
            fx[k] = ws.patches.iter().map(|p| p.forces.fx).sum();
            radii = ws.patches.iter().map(|p| p.rolling_radius).collect();
        }
        let mean_radius = (fx[1] - fx[0]) / (f * (spins[1] - spins[0]) / v);
        let (lo, hi) = (radii[0].min(radii[1]), radii[0].max(radii[1]));
        eprintln!("patch radii {radii:?} m, the force's mean radius {mean_radius:.5} m");
        assert!(
            mean_radius >= lo - 1e-6 && mean_radius <= hi + 1e-6,
            "{mean_radius} outside [{lo}, {hi}]"
        );
    }
}
