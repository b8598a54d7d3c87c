//! The head evaluation's tables: one row per clip (held-out or in-sample figures) with a mean
//! row, and one row per synthesis variant with the variant training keeps. `pneuma eval head`,
//! `pneuma train` and `cargo xtask train-default` print them.

use pneuma_core::head::clip_eval::ClipEval;
use pneuma_core::head::evaluate::CrossValidation;
use pneuma_core::head::targets;

/// Prints one line per variant: targets missed on the held-out clips, by how much, the
/// closeness score, the mean CCA (generated, real, chance) and the median speed ratio; then
/// the variant training keeps.
pub fn print_variant_ranks(cv: &CrossValidation) {
    println!(
        "variants, held out (targets missed, summed miss in units of each limit, closeness to real motion: lower is better)"
    );
    println!("variant,missed,miss,closeness,cca_gen,cca_real,cca_chance,speed_ratio_median");
    for e in &cv.evals {
        let (missed, miss, close) = targets::rank(&e.targets(), &e.clips);
        let n = e.clips.len().max(1) as f64;
        let cca = |k: usize| e.clips.iter().map(|c| c.cca[k]).sum::<f64>() / n;
        let mut speed: Vec<f64> = e.clips.iter().map(ClipEval::speed_ratio).collect();
        speed.sort_by(f64::total_cmp);
        println!(
            "{},{missed},{miss:.3},{close:.3},{:.3},{:.3},{:.3},{:.2}",
            e.variant.name(),
            cca(0),
            cca(1),
            cca(2),
            speed.get(speed.len() / 2).copied().unwrap_or(0.0)
        );
    }
    if let Some(best) = cv.best() {
        println!("kept: {}", best.variant.name());
    }
}

/// Prints a per-clip table of held-out (or in-sample) figures and a summary row: CCA with f0
/// on voiced frames (generated, real, chance), mean angles, SD ratio per axis, speeds and their
/// ratio, power above 3 Hz, frozen share and the onset peak speed.
pub fn print_clip_table(clips: &[ClipEval]) {
    println!(
        "clip,frames,cca_gen,cca_real,cca_chance,mean_roll,mean_pitch,mean_yaw,\
sd_ratio_roll,sd_ratio_pitch,sd_ratio_yaw,speed_gen,speed_real,speed_ratio,\
power_above_3hz_gen,power_above_3hz_real,frozen_gen,onset_peak_deg_s"
    );
    for c in clips {
        let m = c.generated.mean_deg;
        let sd = c.sd_ratio();
        println!(
            "{},{},{:.3},{:.3},{:.3},{:+.2},{:+.2},{:+.2},{:.2},{:.2},{:.2},{:.1},{:.1},{:.2},{:.3},{:.3},{:.3},{:.1}",
            c.name,
            c.frames,
            c.cca[0],
            c.cca[1],
            c.cca[2],
            m[0],
            m[1],
            m[2],
            sd[0],
            sd[1],
            sd[2],
            c.generated.mean_speed_deg_s,
            c.real.mean_speed_deg_s,
            c.speed_ratio(),
            c.generated.power_above_3hz,
            c.real.power_above_3hz,
            c.generated.frozen_share,
            c.onset_peak_deg_s
        );
    }
    let n = clips.len().max(1) as f64;
    let mean = |f: &dyn Fn(&ClipEval) -> f64| clips.iter().map(f).sum::<f64>() / n;
    println!(
        "mean,{},{:.3},{:.3},{:.3},{:+.2},{:+.2},{:+.2},{:.2},{:.2},{:.2},{:.1},{:.1},{:.2},{:.3},{:.3},{:.3},{:.1}",
        clips.iter().map(|c| c.frames).sum::<usize>(),
        mean(&|c| c.cca[0]),
        mean(&|c| c.cca[1]),
        mean(&|c| c.cca[2]),
        mean(&|c| c.generated.mean_deg[0]),
        mean(&|c| c.generated.mean_deg[1]),
        mean(&|c| c.generated.mean_deg[2]),
        mean(&|c| c.sd_ratio()[0]),
        mean(&|c| c.sd_ratio()[1]),
        mean(&|c| c.sd_ratio()[2]),
        mean(&|c| c.generated.mean_speed_deg_s),
        mean(&|c| c.real.mean_speed_deg_s),
        mean(&|c| c.speed_ratio()),
        mean(&|c| c.generated.power_above_3hz),
        mean(&|c| c.real.power_above_3hz),
        mean(&|c| c.generated.frozen_share),
        mean(&|c| c.onset_peak_deg_s),
    );
}
