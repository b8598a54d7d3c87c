//! The app's defaults reach the plugin's parameters in its process: live mode (no latency),
//! OSC on, VMC to the avatar app's port. (Its own test binary: the defaults are process-wide.)

use pneuma_plugin::editor::standalone::{set_app_defaults, AppDefaults};
use pneuma_plugin::params::{ModeChoice, OscFormatChoice};
use pneuma_plugin::PneumaParams;

#[test]
fn the_app_runs_live_and_sends_vmc_by_default() {
    let plugin_defaults = PneumaParams::default();
    assert_eq!(plugin_defaults.mode.value(), ModeChoice::Lookahead);
    assert!(!plugin_defaults.osc_enabled.value());
    set_app_defaults(AppDefaults {
        live: true,
        osc_host: "192.168.1.20".into(),
        osc_port: 39540,
        osc_format: OscFormatChoice::Vmc,
    })
    .unwrap();
    let p = PneumaParams::default();
    assert_eq!(p.mode.value(), ModeChoice::Live);
    assert!(p.osc_enabled.value());
    assert_eq!(p.osc_port.value(), 39540);
    assert_eq!(p.osc_format.value(), OscFormatChoice::Vmc);
    assert_eq!(p.osc_host(), "192.168.1.20");
}
