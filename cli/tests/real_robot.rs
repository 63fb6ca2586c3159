//! The KUKA LWR4+ runs as published (robots/kuka-lwr4): `identify` reads
//! them with no flag but the files, at every constraint level, the missing
//! collision mesh a warning (issue 33).

mod common;
use common::bin;

#[test]
fn the_kuka_runs_identify_as_published_at_every_level() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    for level in ["none", "semi", "consistent", "ellipsoid"] {
        let o = bin()
            .args(["identify", "--robot", &s("kuka_lwr4.urdf")])
            .args(["--data", &s("data/measurements_1.npz")])
            .args(["--data", &s("data/measurements_2.npz")])
            .args(["--validate", &s("data/measurements_3.npz")])
            .args(["--constraints", level, "--json"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{level}: {err}");
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert!(v["training_samples"].as_u64().unwrap() > 9000, "{level}");
        assert_eq!(
            v["data_preparation"]["training"].as_array().unwrap().len(),
            2
        );
        let f = &v["data_preparation"]["training"][0];
        assert_eq!(f["rows"], 5027);
        assert!(f["cutoff_from"].as_str().unwrap().contains("from the data"));
        let rms: Vec<f64> = serde_json::from_value(v["validation_rms"].clone()).unwrap();
        assert_eq!(rms.len(), 7);
        assert!(
            rms.iter().all(|x| x.is_finite() && *x < 3.0),
            "{level}: {rms:?}"
        );
        // the mesh the repository never shipped: a warning, at the level that reads meshes
        let warned = err.contains("arm_wrist_convex.stl") && err.contains("link_6.STL");
        assert_eq!(warned, level == "ellipsoid", "{level}: {err}");
        // every body's consistency, whatever the level
        match level {
            "none" => assert_eq!(
                v["all_bodies_consistent"], false,
                "the unconstrained fit is not physical"
            ),
            "consistent" | "ellipsoid" => assert_eq!(v["all_bodies_consistent"], true),
            _ => assert!(v["all_bodies_consistent"].is_boolean()),
        }
    }
}
