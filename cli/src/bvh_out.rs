//! BVH output options of `render` and `speak` (`--bvh`, `--bvh-fps`): whether a BVH is written
//! and at what frame rate. Off unless one of the options is given: `--bvh-fps` alone turns it
//! on, as any `--osc-*` option turns on OSC ([`crate::osc_out::OscArgs::wanted`]). The BVH
//! itself is core's ([`pneuma_core::encode::bvh`]); a rate other than the control frames' is
//! the pose at each instant, interpolated between the frames either side
//! ([`pneuma_core::encode::sink::Resample`]), so `--bvh-fps`
//! changes only the BVH, never the analysis, the breaths or the other outputs.

/// Lowest `--bvh-fps`, frames per second.
pub const MIN_BVH_FPS: f32 = 1.0;
/// Highest `--bvh-fps`, frames per second.
pub const MAX_BVH_FPS: f32 = 1000.0;

/// `--bvh-fps`'s help: the range from [`MIN_BVH_FPS`] and [`MAX_BVH_FPS`].
fn fps_help() -> String {
    format!(
        "Frames per second of the BVH ({MIN_BVH_FPS} to {MAX_BVH_FPS}; default: --frame-rate); \
         turns --bvh on. Only the BVH is resampled (the pose at each 1/FPS s, interpolated between frames): the \
         analysis, the breaths and the other outputs stay at --frame-rate. Blender's importer \
         plays one BVH frame per scene frame: give the scene's rate (24 by default) so the \
         motion keeps the audio's duration"
    )
}

/// The BVH options (flattened into a subcommand's arguments).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct BvhArgs {
    /// Also write the BVH, `<stem>.bvh` (`speech.bvh` from speak): head, neck and chest motion
    /// on a 1.8 m skeleton in metres (also turned on by --bvh-fps).
    #[arg(long)]
    pub bvh: bool,
    /// Frames per second of the BVH (help text: `fps_help`).
    #[arg(long, value_name = "FPS", help = fps_help(), value_parser = crate::options::number)]
    pub bvh_fps: Option<f64>,
}

impl BvhArgs {
    /// Whether a BVH is asked for: `--bvh`, or `--bvh-fps` alone.
    pub fn wanted(&self) -> bool {
        self.bvh || self.bvh_fps.is_some()
    }

    /// The BVH's frame rate when `--bvh-fps` is given (else the control frames' rate is
    /// meant); `Err` naming the option and its range when it lies outside.
    pub fn fps(&self) -> Result<Option<f64>, String> {
        self.bvh_fps
            .map(|fps| {
                let (min, max) = (f64::from(MIN_BVH_FPS), f64::from(MAX_BVH_FPS));
                crate::options::check_range("--bvh-fps", fps, min, max, "fps").map(|()| fps)
            })
            .transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        bvh: BvhArgs,
    }

    fn parse(args: &str) -> BvhArgs {
        Cli::try_parse_from(std::iter::once("pneuma").chain(args.split_whitespace()))
            .map(|c| c.bvh)
            .expect(args)
    }

    #[test]
    fn bvh_fps_alone_turns_the_bvh_on() {
        assert!(!parse("").wanted());
        assert!(parse("--bvh").wanted());
        let fps = parse("--bvh-fps 24");
        assert!(fps.wanted(), "--bvh-fps without --bvh");
        assert_eq!(fps.fps(), Ok(Some(24.0)));
        assert_eq!(parse("--bvh").fps(), Ok(None));
    }

    #[test]
    fn a_rate_outside_the_range_names_the_option() {
        let e = parse("--bvh-fps 0").fps().unwrap_err();
        assert!(e.starts_with("--bvh-fps 0 fps is out of range"), "{e}");
        assert!(parse("--bvh-fps 1001").fps().is_err());
    }
}
