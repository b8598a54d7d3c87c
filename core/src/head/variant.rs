//! The ways of running the synthesis that training compares leave-one-clip-out: which pose term
//! (the paper's mixture or the conditional mean), whether the paper's velocity and acceleration
//! terms take part, the pose smoother, the speed governor, and the unvoiced behaviour.
//!
//! A [`Variant`] only changes the synthesis settings of a model whose GMMs are already fitted,
//! so one fit per fold serves every variant; [`super::train::calibrate_motion`] then calibrates
//! the output gain (and the governor, when on) for it on the training clips.

use super::model_file::{HeadModel, PoseTerm, UnvoicedBehaviour};

/// One way of running the synthesis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Variant {
    /// How the pose terms read the pose densities.
    pub pose_term: PoseTerm,
    /// What the head does on unvoiced frames.
    pub unvoiced: UnvoicedBehaviour,
    /// The paper's velocity and acceleration terms (the densities of |Δθ| and |Δ²θ| given f0
    /// and loudness) take part in the objective; off, only the pose terms do.
    pub motion_terms: bool,
    /// The one-pole pose smoother before the governor, its time constant calibrated on the
    /// training clips ([`super::train::calibrate_motion`]).
    pub smoother: bool,
    /// The speed governor.
    pub governor: bool,
}

impl Variant {
    /// The variant of the models trained before this comparison existed: the paper's mixture
    /// pose term with its motion terms, smoothed and governed, the loudness model unvoiced.
    pub const PREVIOUS: Variant = Variant {
        pose_term: PoseTerm::Mixture,
        unvoiced: UnvoicedBehaviour::LoudnessModel,
        motion_terms: true,
        smoother: true,
        governor: true,
    };

    /// The variant a model's synthesis settings run.
    pub fn of_model(model: &HeadModel) -> Variant {
        let w = &model.synthesis;
        Variant {
            pose_term: w.pose_term,
            unvoiced: model.unvoiced_behaviour,
            motion_terms: w.velocity_weight > 0.0 || w.acceleration_weight > 0.0,
            smoother: w.smoothing_s > 0.0,
            governor: w.speed_target_deg_s > 0.0,
        }
    }

    /// A short name: pose term, unvoiced behaviour and the switched-off parts, e.g.
    /// `cond_mean/return` or `mixture/hold -governor`.
    pub fn name(&self) -> String {
        let pose = match self.pose_term {
            PoseTerm::Mixture => "mixture",
            PoseTerm::ConditionalMean => "cond_mean",
        };
        let mut s = format!("{pose}/{}", self.unvoiced.as_str());
        for (on, part) in [
            (self.motion_terms, "motion_terms"),
            (self.smoother, "smoother"),
            (self.governor, "governor"),
        ] {
            if !on {
                s.push_str(" -");
                s.push_str(part);
            }
        }
        s
    }

    /// The variants the cross-validation compares: every combination of pose term and unvoiced
    /// behaviour with all parts on, and from each of those, each part switched off alone.
    pub fn candidates() -> Vec<Variant> {
        let mut out = Vec::new();
        for pose_term in [PoseTerm::Mixture, PoseTerm::ConditionalMean] {
            for unvoiced in UnvoicedBehaviour::ALL {
                let full = Variant {
                    pose_term,
                    unvoiced,
                    motion_terms: true,
                    smoother: true,
                    governor: true,
                };
                out.push(full);
                out.push(Variant {
                    motion_terms: false,
                    ..full
                });
                out.push(Variant {
                    smoother: false,
                    ..full
                });
                out.push(Variant {
                    governor: false,
                    ..full
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_are_distinct_and_include_the_previous_variant() {
        let c = Variant::candidates();
        let names: std::collections::HashSet<String> = c.iter().map(Variant::name).collect();
        assert_eq!(names.len(), c.len(), "two candidates share a name");
        assert!(c.contains(&Variant::PREVIOUS));
        assert_eq!(Variant::PREVIOUS.name(), "mixture/loudness_model");
        let off = Variant {
            governor: false,
            motion_terms: false,
            ..Variant::PREVIOUS
        };
        assert_eq!(off.name(), "mixture/loudness_model -motion_terms -governor");
    }
}
