//! `identify`'s default, the friction law and the prior's weight chosen
//! from the data (`--friction auto`), from the command line: the table, the
//! JSON's `model_selection`, the chosen law in the model file that
//! `predict` takes, a listed law as before, and a bad list.

mod common;
use common::{TempDir, bin, ok};

#[test]
fn friction_auto_chooses_a_simulated_stribeck_law_and_the_model_file_carries_it() {
    let t = TempDir::new("friction-auto");
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/panda/panda.urdf");
    let (train, val) = (t.0.join("train.csv"), t.0.join("val.csv"));
    for (out, secs, seed) in [(&train, "10", "3"), (&val, "5", "4")] {
        let effects = "coulomb,viscous,stribeck";
        ok(&[
            "simulate",
            "--robot",
            urdf,
            "--seconds",
            secs,
            "--seed",
            seed,
            "--effects",
            effects,
            "--out",
            out.to_str().unwrap(),
        ]);
    }
    let base = [
        "identify",
        "--robot",
        urdf,
        "--data",
        train.to_str().unwrap(),
        "--validate",
        val.to_str().unwrap(),
    ];
    // the default: no --friction, no --weight
    let text = String::from_utf8(ok(&base)).unwrap();
    assert!(
        text.contains("friction law and prior weight chosen by cross-validation")
            && text.contains("← chosen"),
        "{text}"
    );
    let mut json_args = base.to_vec();
    json_args.push("--json");
    let json = ok(&json_args);
    let j: serde_json::Value = serde_json::from_slice(&json).unwrap();
    let sel = &j["model_selection"];
    let chosen = &sel["laws"][sel["chosen"].as_u64().unwrap() as usize];
    assert!(
        chosen["terms"]
            .as_array()
            .unwrap()
            .iter()
            .any(|x| x == "stribeck"),
        "{sel}"
    );
    assert_eq!(j["friction"]["stribeck_velocity"], 0.2);
    // predict with the model file gives identify's held-out error
    let model = t.write("model.json", std::str::from_utf8(&json).unwrap());
    let pred = t.0.join("pred.csv");
    let o = bin()
        .args([
            "predict",
            "--robot",
            urdf,
            "--params",
            model.to_str().unwrap(),
            "--data",
            val.to_str().unwrap(),
            "--out",
            pred.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    let first = j["validation_rms"][0].as_f64().unwrap();
    assert!(
        said.contains(&format!("{first:.4}")),
        "{first:.4} not in {said}"
    );
    // by default the law and the prior's weight are chosen together (one
    // table, no second curve), and the fit takes the chosen weight
    let sel = &j["model_selection"];
    let laws = sel["laws"].as_array().unwrap();
    assert!(laws.len() > 20, "every law at every weight: {}", laws.len());
    assert_eq!(j["weight"], chosen["weight"], "{sel}");
    assert!(j["weight_choice"].is_null(), "no second weight curve");
    // --friction auto with a weight given: the law alone, at that weight
    let mut given = json_args.clone();
    given.extend(["--friction", "auto", "--weight", "1e-6"]);
    let g: serde_json::Value = serde_json::from_slice(&ok(&given)).unwrap();
    assert_eq!(g["model_selection"]["laws"].as_array().unwrap().len(), 20);
    assert_eq!(g["weight"], 1e-6);
    // a listed law: no choice, today's weight, the prepared log streamed
    let mut listed = json_args.clone();
    listed.extend(["--friction", "viscous,coulomb"]);
    let l: serde_json::Value = serde_json::from_slice(&ok(&listed)).unwrap();
    assert!(l["model_selection"].is_null(), "{}", l["model_selection"]);
    assert_eq!(l["weight"], 1e-6);
    assert_eq!(l["timings"]["streamed"], true);
    // (reading overlaps the reduction, on every thread at most)
    let lt = |k: &str| l["timings"][k].as_f64().unwrap();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as f64;
    assert!(lt("filter_s") == 0.0 && lt("reduce_s") * threads >= lt("read_s"));
    // auto in a list is refused by name
    let o = bin()
        .args([
            "identify",
            "--robot",
            urdf,
            "--data",
            train.to_str().unwrap(),
            "--friction",
            "auto,offset",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("auto stands alone"));
}

/// Training files over the 64 MiB the default's choice reads whole are
/// streamed with viscous + Coulomb, and the warning says so (memory stays
/// bounded by default); `--friction auto` still chooses.
#[test]
fn a_large_training_file_is_streamed_with_the_listed_law_by_default() {
    let t = TempDir::new("friction-auto-large");
    let small = t.0.join("small.csv");
    let small_s = small.to_str().unwrap();
    ok(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "2",
        "--out",
        small_s,
    ]);
    let text = std::fs::read_to_string(&small).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let rows: Vec<&str> = lines.collect();
    // the rows repeated with the time running on, past 64 MiB
    let mut out = String::with_capacity(70 << 20);
    out.push_str(header);
    out.push('\n');
    let mut k = 0usize;
    while out.len() <= 65 << 20 {
        let row = rows[k % rows.len()];
        let rest = row.split_once(',').unwrap().1;
        out.push_str(&format!("{},{rest}\n", k as f64 * 1e-3));
        k += 1;
    }
    let large = t.write("large.csv", &out);
    let args = [
        "identify",
        "--robot",
        "cheetah3-leg",
        "--data",
        large.to_str().unwrap(),
        "--json",
    ];
    let j: serde_json::Value = serde_json::from_slice(&ok(&args)).unwrap();
    assert!(j["model_selection"].is_null(), "{}", j["model_selection"]);
    assert_eq!(j["timings"]["streamed"], true);
    assert_eq!(j["weight"], 1e-6);
    let w = j["warnings"].as_array().unwrap();
    assert!(
        w.iter()
            .any(|w| w["kind"] == "law_not_chosen"
                && w["reason"].as_str().unwrap().contains("64 MiB")),
        "{w:?}"
    );
}
