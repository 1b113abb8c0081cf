//! The soft terms of the cost (paper eq. 10–14), listed once. Each [`Term`] says what it measures,
//! how its weight scales with the drawing, and what bounds it from below before any simulation: the
//! floor that lets the sampler skip simulating samples that cannot beat those kept, which must stay
//! under the cost for the skipping to change no result.
//!
//! A new term is a variant here (its weight in the scene's `Weights`, its value in the design file's
//! `Metrics`). A term known from the joints alone is computed in `evaluate::exact_terms`, whose
//! match the compiler makes cover every term, and is its own floor; a term measured on the travel is
//! computed in `evaluate::simulated_terms` and needs its part of `evaluate::simulated_floor` (the
//! test `cost_floor_never_exceeds_the_simulated_cost` holds the floor under the cost). The final
//! refinement takes the square root of each weighted term as a residual.

use crate::scene::Weights;
use std::ops::{Index, IndexMut};

/// A soft term of eq. 14.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Term {
    /// E_acc (eq. 10): the mean squared miss of the body-carried joints at the poses, plus the mean
    /// squared miss of each body's outline vertices. Length².
    Accuracy,
    /// E_smooth (eq. 11): the mean ratio of a joint's path between two poses to the chord. Unitless.
    Smoothness,
    /// E_loc (eq. 12): the mean distance of the joints from the linkage region. Length.
    Location,
    /// E_size (eq. 13): the mean link length. Length.
    Size,
    /// E_trans (ours, not the paper's): how far the smallest transmission angle along the travel
    /// falls short of the comfortable one ([`transmission_shortfall`]). Unitless. The hard limit
    /// (`min_transmission_deg`) alone left the best design riding on it: a linkage near a dead point
    /// needs large forces, wears its pins and jams when printed with clearance.
    Transmission,
}

/// What bounds a term from below before the linkage is simulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Floor {
    /// The term is computed from the joints alone, before any simulation: it is its own floor.
    Exact,
    /// The term needs the simulated travel; the floor of the simulated terms bounds it (with the
    /// others, since they trade against each other).
    Simulated,
}

impl Term {
    /// Every term, in the order the cost sums them.
    pub const ALL: [Term; 5] = [Term::Accuracy, Term::Smoothness, Term::Location, Term::Size, Term::Transmission];

    /// The scene's weight of the term.
    pub fn scene_weight(self, weights: &Weights) -> f64 {
        match self {
            Term::Accuracy => weights.accuracy,
            Term::Smoothness => weights.smoothness,
            Term::Location => weights.location,
            Term::Size => weights.size,
            Term::Transmission => weights.transmission,
        }
    }

    /// The power of length the raw term carries: the scene's weight applies to the term divided by
    /// the body size d to this power, so a weight means the same at any drawing scale.
    pub fn length_power(self) -> i32 {
        match self {
            Term::Accuracy => 2,
            Term::Smoothness | Term::Transmission => 0,
            Term::Location | Term::Size => 1,
        }
    }

    /// What bounds the term before any simulation.
    pub(crate) fn floor(self) -> Floor {
        match self {
            // Its floor is 0: [`transmission_shortfall`] is never negative.
            Term::Accuracy | Term::Smoothness | Term::Transmission => Floor::Simulated,
            Term::Location | Term::Size => Floor::Exact,
        }
    }
}

/// E_trans of a travel whose smallest transmission sine (of the angle's distance from 0° and 180°) is
/// `least_sine`, against the comfortable angle's sine: the squared shortfall relative to the
/// comfortable sine, (1 − s / s_c)² under it and 0 at or above it. Smooth where it starts, 1 at a
/// dead point, and 0.43 at the hard limit's default 10° against 30°.
pub fn transmission_shortfall(least_sine: f64, comfortable_sine: f64) -> f64 {
    if comfortable_sine <= 0.0 || least_sine >= comfortable_sine {
        return 0.0;
    }
    (1.0 - least_sine.max(0.0) / comfortable_sine).powi(2)
}

/// Indexing by [`Term`] for a type holding one value per term.
macro_rules! per_term {
    ($name:ident) => {
        impl Index<Term> for $name {
            type Output = f64;
            fn index(&self, term: Term) -> &f64 {
                &self.0[term as usize]
            }
        }
        impl IndexMut<Term> for $name {
            fn index_mut(&mut self, term: Term) -> &mut f64 {
                &mut self.0[term as usize]
            }
        }
    };
}

/// The soft terms of one linkage, raw (in the drawing's units), indexed by [`Term`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftTerms([f64; Term::ALL.len()]);
per_term!(SoftTerms);

/// The soft-cost weights (paper eq. 14) as factors of the raw terms, indexed by [`Term`]: the scene's
/// weights apply to the scale-free terms E_acc / d², E_smooth, E_loc / d and E_size / d
/// ([`Term::length_power`]), so a weight means the same at any drawing scale (d: the smallest
/// moving body's size).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CostWeights([f64; Term::ALL.len()]);
per_term!(CostWeights);

impl CostWeights {
    /// The factors of the scene's `weights` for a drawing whose body size is `body_size`.
    pub(crate) fn new(weights: &Weights, body_size: f64) -> CostWeights {
        CostWeights(Term::ALL.map(|t| t.scene_weight(weights) / body_size.powi(t.length_power())))
    }

    /// The weighted sum of the soft terms (eq. 14, scale-free).
    pub(crate) fn cost(&self, soft: &SoftTerms) -> f64 {
        Term::ALL.iter().map(|&t| self[t] * soft[t]).sum()
    }

    /// The part of [`CostWeights::cost`] from the terms whose floor is of the kind `floor`.
    pub(crate) fn cost_of(&self, soft: &SoftTerms, floor: Floor) -> f64 {
        Term::ALL.iter().filter(|t| t.floor() == floor).map(|&t| self[t] * soft[t]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_mean_the_same_at_any_drawing_scale() {
        let weights = Weights {
            accuracy: 3.0,
            smoothness: 2.0,
            location: 5.0,
            size: 7.0,
            transmission: 11.0,
            ..Weights::default()
        };
        let mut soft = SoftTerms::default();
        for (t, value) in Term::ALL.into_iter().zip([0.5, 1.5, 2.0, 4.0, 0.25]) {
            soft[t] = value;
        }
        let unit = CostWeights::new(&weights, 1.0).cost(&soft);
        assert_eq!(unit, 3.0 * 0.5 + 2.0 * 1.5 + 5.0 * 2.0 + 7.0 * 4.0 + 11.0 * 0.25);
        // The same linkage drawn ten times larger: lengths ×10, areas ×100, ratios unchanged.
        let mut scaled = soft;
        for t in Term::ALL {
            scaled[t] *= 10f64.powi(t.length_power());
        }
        let cost = CostWeights::new(&weights, 10.0).cost(&scaled);
        assert!((cost - unit).abs() <= 1e-12 * unit, "{cost} against {unit}");
    }

    /// The shortfall against closed forms: none at or above the comfortable angle, 1 at a dead point,
    /// (1 − sin 10° / sin 30°)² at the default hard limit.
    #[test]
    fn transmission_shortfall_is_the_squared_relative_shortfall_of_the_sine() {
        let sin = |deg: f64| deg.to_radians().sin();
        assert_eq!(transmission_shortfall(sin(30.0), sin(30.0)), 0.0);
        assert_eq!(transmission_shortfall(sin(60.0), sin(30.0)), 0.0);
        assert_eq!(transmission_shortfall(0.0, sin(30.0)), 1.0);
        let at_limit = transmission_shortfall(sin(10.0), 0.5);
        assert!((at_limit - (1.0 - 2.0 * sin(10.0)).powi(2)).abs() < 1e-15, "{at_limit}");
        assert_eq!(transmission_shortfall(0.1, 0.0), 0.0, "no comfortable angle asked");
    }
}
