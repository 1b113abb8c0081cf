//! The build a scene asks for, made concrete: a printed model's scale (an `auto` scale decided from
//! the drawing), the print check the synthesis runs at that scale, and what a design's file records
//! about it (whether it can be built so, and if not why, in numbers).
//!
//! **Why the auto scale is decided from the drawing, before the search.** The synthesis compares
//! candidates by costs measured in fractions of the body size; it needs one print check for all of
//! them, so that a cheaper linkage is never refused only because it was judged at another scale. The
//! drawing bounds what the links can be: their joints lie in the linkage region at the first pose (the
//! region a person draws, or everything drawn at the first pose), so a link is at most the region's
//! diagonal long, and links a fraction of it long must still hold two pins. Deciding before the
//! search costs microseconds; the drawing only bounds the links, so when nothing prints at that scale
//! the search runs again at a few larger ones ([`BuildPlan::synthesize`]).
//!
//! **Why 1:1, else the largest scale that fits.** An object that prints at its own size is printed so.
//! Any other is a model, and a model is best as large as the bed takes: its pins are then smallest
//! beside its links, so the print check refuses least. A large object's largest model is also its
//! scale nearest 1:1; a small object is enlarged that far too. At the least enlargement at which the
//! pins fit, the print check refuses far more: the paper's example 6 drawn a hundredth as large keeps
//! 22 valid designs at 50:1 and 440 at 100:1, of about 12,500 candidates each (`stats.valid` of
//! `linkwright design SCENE --build model:50:1`, then `model:100:1`, on
//! `crates/linkwright-core/tests/fixtures/reference-scenes/k1_example6.json` with its coordinates
//! divided by 100; `linkwright bench --sizes` on that file designs it at the scale chosen). Since the series is
//! closed under a factor of 10, the same object drawn 100 times larger or smaller gets the same
//! model, so the same linkage.

use super::error::FabError;
use super::feasibility::FeasibilityCheck;
use super::settings::{Bed, Dims, PrintSettings};
use crate::design::{BuildRecord, DesignFile, Status};
use crate::geom::Aabb;
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::{Build, ModelScale, Problem, Ratio};
use crate::synth::{synthesize_with, Acceptance, Cancelled, Observer, Options, Outcome};

/// The linkage region of a model must be this many times the least spacing of two pins across: a
/// link spans a fraction of the region, and its two pins need that spacing. With the default print
/// settings the region must then be 35–287 mm across, a window wider than any step of the 1-2-5
/// series, so some scale always satisfies both bounds.
pub const PIN_SPACINGS_PER_REGION: f64 = 4.0;

/// At most this many larger scales are tried when the print check refuses every linkage at an `auto`
/// scale ([`BuildPlan::synthesize`]).
pub const AUTO_RETRIES: usize = 3;

/// What is wrong with a drawing's size for a build, with the numbers (at the model's scale).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SizeNote {
    /// The linkage region is larger than the print area at this scale: long links would not fit.
    #[error(
        "at {scale} the linkage region is {reach_mm:.0} mm across, more than the {bed_mm:.0} mm a link can span \
         on the print bed (its diagonal, less a link's width){}",
        fits.map_or(String::new(), |r| format!(": print at {r} or smaller"))
    )]
    TooLarge {
        /// The model's scale.
        scale: Ratio,
        /// The region's diagonal in the model, mm.
        reach_mm: f64,
        /// The longest link the print area takes (its diagonal less a link's width), mm.
        bed_mm: f64,
        /// The largest scale of the series at which it fits.
        fits: Option<Ratio>,
    },
    /// The linkage region is too small at this scale for links with two pins each.
    #[error(
        "at {scale} the linkage region is {reach_mm:.2} mm across, less than the {need_mm:.1} mm links with \
         pins need{}",
        fits.map_or(String::new(), |r| format!(": print at {r} or larger"))
    )]
    TooSmall {
        /// The model's scale.
        scale: Ratio,
        /// The region's diagonal in the model, mm.
        reach_mm: f64,
        /// What the print settings need ([`PIN_SPACINGS_PER_REGION`] pin spacings), mm.
        need_mm: f64,
        /// The smallest scale of the series at which it is large enough.
        fits: Option<Ratio>,
    },
}

/// A scene's build made concrete for one set of print settings.
#[derive(Clone, Debug)]
pub struct BuildPlan {
    /// The build the scene asks for.
    pub asked: Build,
    /// The build designs are checked for: a model's scale decided, or full size.
    pub checked: Build,
    /// Millimetres per unit of the drawing (the real object).
    pub object_mm_per_unit: f64,
    /// What is wrong with the drawing's size for the build (empty when nothing is).
    pub notes: Vec<SizeNote>,
    /// The everything-drawn box, scene units.
    drawn: Aabb,
    /// The drawing's sizes against the print settings.
    sizes: Sizes,
    /// The print check at the model's scale (none for a full-size build).
    check: Option<FeasibilityCheck>,
}

/// How the drawing's size compares with what a model needs, in scene units and millimetres.
#[derive(Clone, Debug)]
struct Sizes {
    /// The linkage region's diagonal, mm of the object.
    reach_mm: f64,
    /// The print area's diagonal (the bed minus its margins): the longest bar that lies on it, mm.
    bed_mm: f64,
    /// A link's width, mm.
    link_width: f64,
    /// What the region's diagonal must be in the model, mm.
    need_mm: f64,
}

impl Sizes {
    fn new(problem: &Problem, settings: &PrintSettings) -> Sizes {
        Sizes {
            reach_mm: problem.region.aabb().diagonal() * problem.units.millimetres(),
            bed_mm: bed_diagonal_mm(&settings.bed),
            link_width: settings.link_width,
            need_mm: PIN_SPACINGS_PER_REGION * Dims::new(settings, 1.0).min_joint_spacing(),
        }
    }
    /// Whether a link as long as the region fits the print area at `scale`, along its diagonal.
    fn fits(&self, scale: Ratio) -> bool {
        self.link_fits(scale, self.reach_mm)
    }
    /// Whether a link `length_mm` long (in the object) fits the print area at `scale`.
    fn link_fits(&self, scale: Ratio, length_mm: f64) -> bool {
        scale.factor() * length_mm + self.link_width <= self.bed_mm
    }
    /// Whether the region is large enough for links with pins at `scale`.
    fn large_enough(&self, scale: Ratio) -> bool {
        scale.factor() * self.reach_mm >= self.need_mm
    }
    /// 1:1 when it fits and is large enough, else the largest scale of the series that fits and is
    /// large enough: a large object's nearest to 1:1, a small object's model as large as the bed
    /// takes (an enlarged model is not the object's size anyway, and the larger it is the smaller its
    /// pins are beside its links). When none is both, the largest that fits (the bed is a hard limit,
    /// and small links are refused one by one); when none fits, the smallest.
    fn auto(&self) -> Ratio {
        let series = Ratio::series();
        let both: Vec<Ratio> = series.iter().copied().filter(|&r| self.fits(r) && self.large_enough(r)).collect();
        if both.contains(&Ratio::ONE) {
            return Ratio::ONE;
        }
        let largest = |rs: &mut dyn Iterator<Item = Ratio>| rs.max_by(|a, b| a.factor().total_cmp(&b.factor()));
        largest(&mut both.into_iter())
            .or_else(|| largest(&mut series.iter().copied().filter(|&r| self.fits(r))))
            .unwrap_or(series[series.len() - 1])
    }
    /// Whether a retry may print at `scale`: its region's diagonal is at most twice the longest link
    /// the bed takes (links are seldom as long as the region's diagonal).
    fn may_retry(&self, scale: Ratio) -> bool {
        scale.factor() * self.reach_mm <= 2.0 * self.bed_mm
    }
    /// What is wrong at `scale`.
    fn notes(&self, scale: Ratio) -> Vec<SizeNote> {
        let series = Ratio::series();
        let mut notes = Vec::new();
        if !self.fits(scale) {
            notes.push(SizeNote::TooLarge {
                scale,
                reach_mm: scale.factor() * self.reach_mm,
                bed_mm: self.bed_mm - self.link_width,
                fits: series.iter().copied().find(|&r| self.fits(r)),
            });
        }
        if !self.large_enough(scale) {
            notes.push(SizeNote::TooSmall {
                scale,
                reach_mm: scale.factor() * self.reach_mm,
                need_mm: self.need_mm,
                fits: series.iter().rev().copied().find(|&r| self.large_enough(r)),
            });
        }
        notes
    }
}

/// The print area's diagonal (the bed minus its margins), mm: a part turned along it is the longest
/// that lies on the bed.
fn bed_diagonal_mm(bed: &Bed) -> f64 {
    (bed.width - 2.0 * bed.margin).hypot(bed.depth - 2.0 * bed.margin)
}

impl BuildPlan {
    /// The scene's build (`problem.build`) made concrete with `settings`: an `auto` model scale
    /// decided from the drawing, and the print check at the model's scale.
    pub fn new(problem: &Problem, settings: &PrintSettings) -> BuildPlan {
        let sizes = Sizes::new(problem, settings);
        match problem.build {
            Build::Model(ModelScale::Auto) => {
                let scale = sizes.auto();
                BuildPlan::at(problem, settings, sizes, Build::Model(ModelScale::Fixed(scale)))
            }
            checked => BuildPlan::at(problem, settings, sizes, checked),
        }
    }

    /// The plan that checks designs for `checked` (a model's scale fixed, or full size).
    fn at(problem: &Problem, settings: &PrintSettings, sizes: Sizes, checked: Build) -> BuildPlan {
        let (notes, check) = match checked {
            Build::Model(ModelScale::Fixed(scale)) => {
                (sizes.notes(scale), Some(FeasibilityCheck::new(problem, settings, scale)))
            }
            _ => (Vec::new(), None),
        };
        BuildPlan {
            asked: problem.build,
            checked,
            object_mm_per_unit: problem.units.millimetres(),
            notes,
            drawn: drawn_box(problem),
            sizes,
            check,
        }
    }

    /// Runs the synthesis (`options`, whose own check is replaced by this build's) for this build.
    /// With an `auto` scale, when the print check refused every valid linkage at the scale the drawing
    /// decided, or the search found none in a model whose region is under twice the least (the pins
    /// crowd it), the search runs again at the next larger scales of the series whose region is at
    /// most twice what the bed takes, at most [`AUTO_RETRIES`] of them, until one gives a design that
    /// prints; when the search found none in a model that is not crowded, at the next larger scale
    /// alone. The
    /// drawing bounds the links only from above, and how far apart their joints are shows only in the
    /// search. Returns the plan of the outcome kept (the first printable one, else the
    /// first).
    pub fn synthesize(
        self,
        problem: &Problem,
        settings: &PrintSettings,
        options: &Options,
        observer: &dyn Observer,
    ) -> Result<(BuildPlan, Outcome), Cancelled> {
        let run = |plan: &BuildPlan| {
            let options = Options { printable: plan.acceptance(), ..*options };
            synthesize_with(problem, &options, observer)
        };
        let first = run(&self)?;
        let (Build::Model(ModelScale::Auto), Some(scale)) = (self.asked, self.model_scale()) else {
            return Ok((self, first));
        };
        // The pin spacing also thins the samples before any check counts them, so a search with no
        // design at all may be the scale's doing too: in a model whose region is crowded (under twice
        // the least), up to AUTO_RETRIES larger scales are tried; elsewhere the next larger scale alone,
        // and then the poses are at fault. Both even where the region's diagonal does not fit the bed
        // (`Sizes::may_retry`).
        let refused = |o: &Outcome| o.unbuildable || o.best.is_none();
        if !refused(&first) {
            return Ok((self, first));
        }
        let crowded = scale.factor() * self.sizes.reach_mm < 2.0 * self.sizes.need_mm;
        let tries = if first.unbuildable || crowded { AUTO_RETRIES } else { 1 };
        let larger: Vec<Ratio> = Ratio::series()
            .into_iter()
            .rev()
            .filter(|r| r.factor() > scale.factor() && self.sizes.may_retry(*r))
            .take(tries)
            .collect();
        for scale in larger {
            let plan = BuildPlan::at(problem, settings, self.sizes.clone(), Build::Model(ModelScale::Fixed(scale)));
            let outcome = run(&plan)?;
            if !refused(&outcome) {
                return Ok((plan, outcome));
            }
        }
        Ok((self, first))
    }

    /// The model's scale (none for a full-size build).
    pub fn model_scale(&self) -> Option<Ratio> {
        match self.checked {
            Build::Model(ModelScale::Fixed(scale)) => Some(scale),
            _ => None,
        }
    }

    /// Millimetres of the printed model per unit of the drawing (none for a full-size build).
    pub fn model_mm_per_unit(&self) -> Option<f64> {
        self.model_scale().map(|s| self.object_mm_per_unit * s.factor())
    }

    /// The check every design must pass for this build: printable at the model's scale (none for a
    /// full-size build, whose parts are cut to size).
    pub fn acceptance(&self) -> Option<&dyn Acceptance> {
        self.check.as_ref().map(|c| c as &dyn Acceptance)
    }

    /// The model's extent, width and height in millimetres: everything drawn at its scale.
    pub fn model_mm(&self) -> Option<[f64; 2]> {
        self.model_mm_per_unit().map(|mm| [self.drawn.width() * mm, self.drawn.height() * mm])
    }

    /// What a design file records of the build for `outcome`: whether its best design can be built
    /// so, and if not why, with the numbers and what would help.
    pub fn record(&self, outcome: &Outcome) -> BuildRecord {
        let buildable = !outcome.unbuildable;
        let reason = match (&outcome.best, &self.check) {
            (Some(best), Some(check)) if !buildable => {
                let error = check.diagnose(&best.mechanism, &best.trace).err();
                Some(self.unbuildable_reason(&best.mechanism, error))
            }
            _ => None,
        };
        BuildRecord { asked: self.asked, checked: self.checked, buildable, reason, model_mm: self.model_mm() }
    }

    /// The design file of `outcome` (a search of `problem` for this build), with the build recorded;
    /// when there is no design and the drawing's size does not suit the build, its reason says that
    /// instead (the search's own reason would blame the poses).
    pub fn design_file(&self, problem: &Problem, outcome: &Outcome) -> DesignFile {
        let mut file = DesignFile::from_outcome(problem, outcome);
        file.build = Some(self.record(outcome));
        if file.status == Status::NoSolution && !self.notes.is_empty() {
            let size: Vec<String> = self.notes.iter().map(|n| n.to_string()).collect();
            file.reason = Some(format!(
                "The drawing's size does not suit the build {}: {}; the search found no linkage at this scale.",
                self.asked,
                size.join("; ")
            ));
        }
        file
    }

    /// Why `mechanism` cannot be printed at the model's scale (the print check's `error`), in numbers,
    /// with the scale that would do or the full-size build.
    fn unbuildable_reason(&self, mechanism: &Mechanism, error: Option<FabError>) -> String {
        let Some(scale) = self.model_scale() else { return String::new() };
        let mm = self.object_mm_per_unit;
        let f = scale.factor();
        let (shortest, longest) = link_extremes(mechanism);
        let series = Ratio::series();
        match error {
            // A link too long for the bed is said in its length; otherwise some other part (a body's
            // connector, the frame) is what fits in no turn, and the check's own numbers say so.
            Some(FabError::OffBed { parts, square_bed_mm, max_scale, .. })
                if self.sizes.link_fits(scale, longest * mm) =>
            {
                let fits = series.iter().find(|r| r.factor() <= f * max_scale);
                format!(
                    "{parts} fit the print bed in no turn at {scale} (they need a bed {square_bed_mm:.0} mm square): \
                     {}build it full size",
                    fits.map_or(String::new(), |r| format!("print at {r} or smaller, or "))
                )
            }
            Some(FabError::OffBed { .. }) => {
                let fits = series.iter().find(|r| self.sizes.link_fits(**r, longest * mm));
                format!(
                    "its links are up to {:.0} mm long ({:.0} mm in the model at {scale}), more than the {:.0} mm a \
                     link can span on the print bed: {}build it full size",
                    longest * mm,
                    longest * mm * f,
                    self.sizes.bed_mm - self.sizes.link_width,
                    fits.map_or(String::new(), |r| format!("print at {r} or smaller, or "))
                )
            }
            Some(FabError::JointsTooClose { need_mm, .. }) => {
                let fits = series.iter().rev().find(|r| r.factor() * shortest * mm >= need_mm);
                format!(
                    "two joints of one link are {:.1} mm apart ({:.2} mm in the model at {scale}), closer than the \
                     {need_mm:.1} mm two pins need: {}build it full size",
                    shortest * mm,
                    shortest * mm * f,
                    fits.map_or(String::new(), |r| format!("print at {r} or larger, or "))
                )
            }
            Some(e) => format!("at {scale}, {e}; or build it full size"),
            None => format!("it cannot be printed at {scale}; build it full size"),
        }
    }
}

/// The scale a design is printed at: the scene's model scale when it fixes one; with `auto`, the
/// scale `design` was checked at when it records one for `auto`, else the one the drawing decides
/// ([`BuildPlan`]). A full-size build's printed model takes the `auto` scale too.
pub fn model_scale(problem: &Problem, design: Option<&DesignFile>, settings: &PrintSettings) -> Ratio {
    if let Build::Model(ModelScale::Fixed(scale)) = problem.build {
        return scale;
    }
    let recorded = design.and_then(|d| d.build.as_ref()).and_then(|b| match (b.asked, b.checked) {
        (Build::Model(ModelScale::Auto), Build::Model(ModelScale::Fixed(scale))) => Some(scale),
        _ => None,
    });
    recorded.unwrap_or_else(|| Sizes::new(problem, settings).auto())
}

/// Everything drawn, width and height at `mm_per_unit` millimetres per unit.
pub(crate) fn drawn_mm(problem: &Problem, mm_per_unit: f64) -> [f64; 2] {
    let drawn = drawn_box(problem);
    [drawn.width() * mm_per_unit, drawn.height() * mm_per_unit]
}

/// The shortest and the longest distance between two joints of one link (scene units), with the
/// slider's guide as a link as long as its stroke.
fn link_extremes(mechanism: &Mechanism) -> (f64, f64) {
    let (mut shortest, mut longest) = (f64::INFINITY, 0.0f64);
    for part in mechanism.topology.parts.iter().filter(|p| p.kind == PartKind::Link) {
        for (i, &a) in part.joints.iter().enumerate() {
            for &b in &part.joints[i + 1..] {
                let d = mechanism.joints[a].distance(mechanism.joints[b]);
                shortest = shortest.min(d);
                longest = longest.max(d);
            }
        }
    }
    (shortest, longest)
}

/// The box around everything drawn: fixed bodies, moving bodies at every pose and the linkage region.
fn drawn_box(problem: &Problem) -> Aabb {
    let mut boxes = problem.fixed.iter().map(|f| f.aabb()).collect::<Vec<_>>();
    for b in &problem.bodies {
        boxes.extend(b.poses.iter().map(|pose| b.outline.transformed(pose).aabb()));
    }
    boxes.push(problem.region.aabb());
    boxes.into_iter().reduce(|a, b| a.union(&b)).expect("the region is always there")
}
