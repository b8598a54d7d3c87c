//! The head model file: round trip, and each rejection (NaN, non-positive-definite covariance,
//! wrong dimensions, weights not summing to 1, unknown version or format) with a clear error.

use pneuma_core::head::{GmmError, HeadModel, HeadModelError};
use serde_json::Value;

fn default_json() -> Value {
    serde_json::from_str(HeadModel::default_model_json()).unwrap()
}

fn load(v: &Value) -> Result<HeadModel, HeadModelError> {
    HeadModel::from_json(&serde_json::to_string(v).unwrap())
}

#[test]
fn round_trip_is_exact() {
    let m = HeadModel::default_model();
    let text = m.to_json();
    let back = HeadModel::from_json(&text).unwrap();
    assert_eq!(&back, m);
    assert_eq!(back.to_json(), text);
}

#[test]
fn rejects_nan() {
    let mut v = default_json();
    // NaN cannot be written in JSON; a number out of f64 range parses as an error, and a null
    // where a number belongs is rejected by the layout. Both name the problem.
    v["voiced"]["pitch"]["means"][0][1] = Value::Null;
    assert!(matches!(load(&v), Err(HeadModelError::Json(_))));
    let text =
        HeadModel::default_model_json().replacen("\"pose_weight\": 0.2", "\"pose_weight\": NaN", 1);
    assert!(matches!(
        HeadModel::from_json(&text),
        Err(HeadModelError::Json(_))
    ));
    let huge = HeadModel::default_model_json().replacen(
        "\"pose_weight\": 0.2",
        "\"pose_weight\": 1e999",
        1,
    );
    assert!(HeadModel::from_json(&huge).is_err());
}

#[test]
fn rejects_a_covariance_that_is_not_positive_definite() {
    let mut v = default_json();
    v["voiced"]["velocity"]["covariances"][2][0][0] = serde_json::json!(-1.0);
    let e = load(&v).unwrap_err();
    assert_eq!(
        e,
        HeadModelError::Gmm {
            group: "voiced",
            feature: "velocity",
            source: GmmError::NotPositiveDefinite(2)
        }
    );
    assert!(e.to_string().contains("positive definite"));
    let mut v = default_json();
    v["unvoiced"]["roll"]["covariances"][0][0][1] = serde_json::json!(1e3);
    assert!(matches!(
        load(&v),
        Err(HeadModelError::Gmm {
            source: GmmError::NotSymmetric(0),
            ..
        })
    ));
}

#[test]
fn rejects_wrong_dimensions() {
    let mut v = default_json();
    v["voiced"]["roll"]["means"][0]
        .as_array_mut()
        .unwrap()
        .pop();
    assert!(matches!(
        load(&v),
        Err(HeadModelError::Dimension {
            group: "voiced",
            feature: "roll",
            got: 2,
            want: 3
        })
    ));
    let mut v = default_json();
    v["voiced"]["velocity"]["covariances"][1][2]
        .as_array_mut()
        .unwrap()
        .pop();
    assert!(matches!(
        load(&v),
        Err(HeadModelError::Gmm {
            feature: "velocity",
            source: GmmError::Shape { .. },
            ..
        })
    ));
    let mut v = default_json();
    v["unvoiced"]["pitch"]["weights"]
        .as_array_mut()
        .unwrap()
        .pop();
    assert!(matches!(load(&v), Err(HeadModelError::Json(_))));
}

#[test]
fn rejects_weights_not_summing_to_one() {
    let mut v = default_json();
    let w = v["voiced"]["acceleration"]["weights"][0].as_f64().unwrap();
    v["voiced"]["acceleration"]["weights"][0] = serde_json::json!(w + 0.1);
    let e = load(&v).unwrap_err();
    assert!(
        matches!(
            e,
            HeadModelError::Gmm {
                source: GmmError::WeightSum(_),
                ..
            }
        ),
        "{e}"
    );
    let mut v = default_json();
    v["voiced"]["roll"]["weights"][0] = serde_json::json!(-0.1);
    assert!(matches!(
        load(&v),
        Err(HeadModelError::Gmm {
            source: GmmError::Weight { .. },
            ..
        })
    ));
}

#[test]
fn rejects_unknown_version_format_units_and_settings() {
    let mut v = default_json();
    v["version"] = serde_json::json!(2);
    let e = load(&v).unwrap_err();
    assert_eq!(e, HeadModelError::Version(2));
    assert!(e.to_string().contains("version 2"));
    let mut v = default_json();
    v["format"] = serde_json::json!("something-else");
    assert!(matches!(load(&v), Err(HeadModelError::Format(_))));
    let mut v = default_json();
    v["normalisation"]["f0"] = serde_json::json!("hz");
    assert!(matches!(
        load(&v),
        Err(HeadModelError::Normalisation { field: "f0", .. })
    ));
    let mut v = default_json();
    v["unvoiced"]["behaviour"] = serde_json::json!("dance");
    assert!(matches!(load(&v), Err(HeadModelError::Behaviour(_))));
    let mut v = default_json();
    v["synthesis"]["output_gain"] = serde_json::json!([1.0, 0.0, 1.0]);
    assert!(matches!(
        load(&v),
        Err(HeadModelError::OutOfRange {
            name: "synthesis.output_gain",
            ..
        })
    ));
    assert!(matches!(
        HeadModel::from_json("not json"),
        Err(HeadModelError::Json(_))
    ));
}
