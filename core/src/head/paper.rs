//! The seed paper's own trained models as a reference beside ours (van Welbergen et al., IVA
//! 2015; their repository herwinvw/VisualProsody, `RuntimeAndExperiment/resource/
//! gmmVoiced{roll,pitch,yaw,v,a}11.xml`). Those files carry no licence, so they are never part of
//! this project: the evaluation reads them from a folder the user gives.
//!
//! - [`parse_gmm_xml`] reads their format: `<gmm k="K">` with `<lambdas>` (`<lambda val="w"/>`),
//!   `<mus>` (`<mu val="x f0 rms"/>`) and `<sigmas>` (`<sigma val="9 entries, row-major"/>`).
//! - [`PaperSynth`] runs them as the paper does (their `VisualProsodyLeNumericalDiff` with the
//!   weights of their runtime): features are the raw f0 in Hz and the linear RMS energy (their
//!   openSMILE `F0_sma` and `pcm_RMSenergy_sma`, here [`FeatureFrame::f0_hz`] and
//!   10^(`rms_db`/20)); velocity and acceleration in degrees per frame at their 120 Hz; the
//!   objective `−0.2·Σ log p(angle, f0, E) − 2/8·log p(v, f0, E) − 1/16·log p(a, f0, E)` is
//!   minimised by box-bounded BFGS (±90°) from the previous pose; unvoiced frames (f0 = 0) keep
//!   the head still. No gain, smoother or governor. Angles come out relative to the model's own
//!   mean pose (the voiced GMMs' marginal means): their training motion is in the motion-capture
//!   frame of one actress, not around her mean pose.

use glam::DVec3;
use thiserror::Error;

use super::bfgs::{minimize, BfgsConfig};
use super::gmm::{Conditioner, Gaussian, Gmm, GmmError, Mixture1, MAX_DIM};
use crate::analysis::FeatureFrame;

/// File names of the paper's five voiced models in a folder, in our feature order (roll, pitch,
/// yaw, velocity, acceleration).
pub const PAPER_MODEL_FILES: [&str; 5] = [
    "gmmVoicedroll11.xml",
    "gmmVoicedpitch11.xml",
    "gmmVoicedyaw11.xml",
    "gmmVoicedv11.xml",
    "gmmVoiceda11.xml",
];

/// Frame rate the paper's velocity and acceleration are counted at, Hz.
pub const PAPER_FRAME_RATE_HZ: f64 = 120.0;
/// The paper's objective weights: pose, velocity (their 2 × 1/8), acceleration (1/16).
const WEIGHTS: [f64; 3] = [0.2, 0.25, 0.0625];
/// Their search box, degrees.
const BOUND_DEG: f64 = 90.0;

/// Errors reading one of the paper's GMM files; each says what to fix.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PaperModelError {
    /// A tag or attribute is missing or malformed.
    #[error("{0} (expected the paper's <gmm k=..> file with <lambdas>, <mus> and <sigmas>)")]
    Format(String),
    /// The numbers do not form a valid mixture.
    #[error("the mixture is invalid: {0}")]
    Gmm(#[from] GmmError),
}

/// The `val` attributes of every `<tag .../>` element in `text`, parsed as numbers.
fn values(text: &str, tag: &str) -> Result<Vec<Vec<f64>>, PaperModelError> {
    let open = format!("<{tag} ");
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(&open) {
        rest = &rest[at + open.len()..];
        let end = rest
            .find('>')
            .ok_or_else(|| PaperModelError::Format(format!("<{tag}> is not closed")))?;
        let attrs = &rest[..end];
        let v = attrs
            .find("val=\"")
            .map(|i| &attrs[i + 5..])
            .and_then(|s| s.find('"').map(|j| &s[..j]))
            .ok_or_else(|| PaperModelError::Format(format!("<{tag}> has no val=\"...\"")))?;
        let nums = v
            .split_whitespace()
            .map(|x| {
                x.parse::<f64>().map_err(|_| {
                    PaperModelError::Format(format!("<{tag}> value `{x}` is not a number"))
                })
            })
            .collect::<Result<Vec<f64>, _>>()?;
        out.push(nums);
        rest = &rest[end..];
    }
    Ok(out)
}

/// Parses one of the paper's GMM files (3-D: motion feature, f0 in Hz, RMS energy).
pub fn parse_gmm_xml(text: &str) -> Result<Gmm, PaperModelError> {
    if !text.contains("<gmm") {
        return Err(PaperModelError::Format("no <gmm> element".into()));
    }
    let lambdas = values(text, "lambda")?;
    let mus = values(text, "mu")?;
    let sigmas = values(text, "sigma")?;
    let k = lambdas.len();
    if k == 0 || mus.len() != k || sigmas.len() != k {
        return Err(PaperModelError::Format(format!(
            "{k} lambdas, {} mus and {} sigmas: they must be equally many and at least one",
            mus.len(),
            sigmas.len()
        )));
    }
    let dim = mus[0].len();
    if !(1..=MAX_DIM).contains(&dim) {
        return Err(PaperModelError::Format(format!(
            "means of {dim} entries: 1 to {MAX_DIM} are supported"
        )));
    }
    let mut comps = Vec::with_capacity(k);
    for c in 0..k {
        if lambdas[c].len() != 1 || mus[c].len() != dim || sigmas[c].len() != dim * dim {
            return Err(PaperModelError::Format(format!(
                "component {c}: a lambda of one number, a mu of {dim} and a sigma of {} are needed",
                dim * dim
            )));
        }
        let mut g = Gaussian {
            weight: lambdas[c][0],
            mean: [0.0; MAX_DIM],
            cov: [[0.0; MAX_DIM]; MAX_DIM],
        };
        for i in 0..dim {
            g.mean[i] = mus[c][i];
            for j in 0..dim {
                g.cov[i][j] = sigmas[c][i * dim + j];
            }
        }
        comps.push(g);
    }
    // Their weights sum to 1 within printing precision; make it exact.
    let sum: f64 = comps.iter().map(|g| g.weight).sum();
    if (sum - 1.0).abs() < 1e-6 {
        comps.iter_mut().for_each(|g| g.weight /= sum);
    }
    Ok(Gmm::new(dim, &comps)?)
}

/// The paper's five voiced GMMs run with the paper's objective and features.
#[derive(Debug, Clone)]
pub struct PaperSynth {
    conds: [Conditioner; 5],
    mix: [Mixture1; 5],
    /// The model's mean pose (roll, pitch, yaw), degrees in its own frame.
    mean_pose: DVec3,
    prev1: DVec3,
    prev2: DVec3,
    bfgs: BfgsConfig,
}

impl PaperSynth {
    /// A synthesis with the five voiced GMMs in [`PAPER_MODEL_FILES`] order (3-D each).
    pub fn new(gmms: &[Gmm; 5]) -> Result<PaperSynth, PaperModelError> {
        if let Some(g) = gmms.iter().find(|g| g.dim() != 3) {
            return Err(PaperModelError::Format(format!(
                "a voiced model has dimension {}: (feature, f0, RMS energy) needs 3",
                g.dim()
            )));
        }
        let marginal_mean = |g: &Gmm| g.components().map(|c| c.weight * c.mean[0]).sum::<f64>();
        let mean_pose = DVec3::new(
            marginal_mean(&gmms[0]),
            marginal_mean(&gmms[1]),
            marginal_mean(&gmms[2]),
        );
        Ok(PaperSynth {
            conds: [0, 1, 2, 3, 4].map(|k| gmms[k].conditioner()),
            mix: [Mixture1::default(); 5],
            mean_pose,
            prev1: mean_pose,
            prev2: mean_pose,
            bfgs: BfgsConfig::default(),
        })
    }

    /// The pose for one frame at `frame_rate_hz`: (roll, pitch, yaw) in degrees around the
    /// model's mean pose.
    pub fn process(&mut self, frame: &FeatureFrame, frame_rate_hz: f64) -> [f64; 3] {
        let f0 = frame.f0_hz as f64;
        let next = if frame.voiced && f0 > 0.0 && frame.rms_db.is_finite() {
            let rms = 10f64.powf(frame.rms_db as f64 / 20.0);
            for (c, m) in self.conds.iter().zip(self.mix.iter_mut()) {
                c.condition(&[f0, rms], m);
            }
            self.argmax(frame_rate_hz / PAPER_FRAME_RATE_HZ)
        } else {
            self.prev1
        };
        self.prev2 = self.prev1;
        self.prev1 = next;
        (next - self.mean_pose).to_array()
    }

    /// The objective's argmax; `per_frame` turns a difference per our frame into one per
    /// their 120 Hz frame.
    fn argmax(&self, per_frame: f64) -> DVec3 {
        let (p1, p2, mix) = (self.prev1, self.prev2, &self.mix);
        let [wp, wv, wa] = WEIGHTS;
        let eps2 = 1e-6;
        let objective = |x: DVec3| {
            let mut j = 0.0;
            let mut g = DVec3::ZERO;
            for i in 0..3 {
                let (lp, d) = mix[i].log_pdf_grad(x[i]);
                j -= wp * lp;
                g[i] -= wp * d;
            }
            let dv = x - p1;
            let rv = (dv.length_squared() + eps2).sqrt();
            let (lv, dlv) = mix[3].log_pdf_grad(per_frame * rv);
            j -= wv * lv;
            g -= dv * (wv * dlv * per_frame / rv);
            let da = x - 2.0 * p1 + p2;
            let ra = (da.length_squared() + eps2).sqrt();
            let s = per_frame * per_frame;
            let (la, dla) = mix[4].log_pdf_grad(s * ra);
            j -= wa * la;
            g -= da * (wa * dla * s / ra);
            (j, g)
        };
        let bound = DVec3::splat(BOUND_DEG);
        let x = minimize(objective, p1, -bound, bound, &self.bfgs).x;
        if x.is_finite() {
            x
        } else {
            p1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file in the paper's layout: two components over (feature, f0, rms).
    fn two_components(shift: f64) -> String {
        format!(
            r#"<gmm k="2">
  <lambdas>
    <lambda val="0.25"/>
    <lambda val="0.75"/>
  </lambdas>
  <mus>
    <mu val="{a} 150 0.05"/>
    <mu val="{b} 250 0.1"/>
  </mus>
  <sigmas>
    <sigma val="4 10 0 10 400 0 0 0 0.0004"/>
    <sigma val="4 10 0 10 400 0 0 0 0.0004"/>
  </sigmas>
</gmm>"#,
            a = -2.0 + shift,
            b = 2.0 + shift
        )
    }

    #[test]
    fn parses_the_layout_and_rejects_broken_files() {
        let g = parse_gmm_xml(&two_components(0.0)).unwrap();
        assert_eq!((g.dim(), g.len()), (3, 2));
        let c: Vec<&Gaussian> = g.components().collect();
        assert_eq!(c[1].mean, [2.0, 250.0, 0.1]);
        assert_eq!(c[0].cov[0][1], 10.0);
        let short = two_components(0.0).replace("<mu val=\"2 250 0.1\"/>", "");
        let err = parse_gmm_xml(&short).unwrap_err().to_string();
        assert!(err.contains("2 lambdas, 1 mus and 2 sigmas"), "{err}");
        let nan = two_components(0.0).replace("0.0004\"/>\n  </sigmas>", "x\"/>\n  </sigmas>");
        let err = parse_gmm_xml(&nan).unwrap_err().to_string();
        assert!(err.contains("`x` is not a number"), "{err}");
        assert!(parse_gmm_xml("<html/>").is_err());
    }

    #[test]
    fn the_head_follows_f0_where_the_model_says_and_holds_when_unvoiced() {
        // Pose means rise with f0 (covariance 10 between angle and f0): a higher voice pulls
        // every angle up.
        let gmm = parse_gmm_xml(&two_components(0.0)).unwrap();
        let motion = parse_gmm_xml(&two_components(3.0)).unwrap();
        let mut s =
            PaperSynth::new(&[gmm.clone(), gmm.clone(), gmm, motion.clone(), motion]).unwrap();
        let frame = |f0_hz: f32, voiced: bool| FeatureFrame {
            f0_hz,
            voiced,
            rms_db: -20.0,
            ..FeatureFrame::default()
        };
        let mut low = [0.0; 3];
        for _ in 0..240 {
            low = s.process(&frame(140.0, true), 120.0);
        }
        let mut high = [0.0; 3];
        for _ in 0..240 {
            high = s.process(&frame(260.0, true), 120.0);
        }
        assert!(high[1] > low[1] + 1.0, "low {low:?} high {high:?}");
        assert_eq!(s.process(&frame(0.0, false), 120.0), high);
    }
}
