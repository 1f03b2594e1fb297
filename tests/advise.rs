//! `pathlab advise` on the study scene predicts the samples each method needs as the study's
//! table ranks them (best, mis, nee, cosine, plain, with gaps of 2x or more between neighbours,
//! README "Reproducing the study"), orders its rows by predicted time, and `--verify` renders
//! its winner to the target. The ranking asserted is by work, which no machine changes; no time
//! is asserted.

use std::process::Command;

#[test]
fn advise_ranks_the_methods_like_the_study_and_verifies_the_winner() {
    let out = Command::new(env!("CARGO_BIN_EXE_pathlab"))
        .arg("advise")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml"))
        .args(["--size", "256x128", "--target-rel-error", "1e-4", "--pilot-seconds", "1", "--methods", "plain,cosine,nee,mis,best"])
        .args(["--verify", "--json"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let advice = report["advice"].as_array().unwrap();
    println!("{}", serde_json::to_string_pretty(&report).unwrap());
    // The study's ranking is by the samples each method needs to reach the target, which no
    // machine changes; what each sample costs differs by machine (this test failed on an NVIDIA
    // H200 when it asserted the order by time), so the order by predicted time is only checked
    // to be advise's own, and its winner is the one verified.
    let spp = |m: &str| advice.iter().find(|a| a["method"] == m).and_then(|a| a["predicted_spp"].as_f64()).unwrap_or_else(|| panic!("no predicted_spp for {m}"));
    let by_work = ["best", "mis", "nee", "cosine", "plain"];
    for pair in by_work.windows(2) {
        assert!(spp(pair[0]) < spp(pair[1]), "{} needs {} samples per pixel, {} {}: the study's ranking", pair[0], spp(pair[0]), pair[1], spp(pair[1]));
    }
    assert!(spp("plain") > 10.0 * spp("best"), "best needs {} samples per pixel, plain {}", spp("best"), spp("plain"));
    let seconds: Vec<f64> = advice.iter().map(|a| a["predicted_seconds"].as_f64().unwrap()).collect();
    assert!(seconds.windows(2).all(|w| w[0] <= w[1]), "advise's rows are not ordered by predicted time: {seconds:?}");
    for a in advice {
        assert!(a["predicted_seconds"].as_f64().is_some_and(|t| t > 0.0), "{a}");
        let (lo, hi) = (a["range"][0].as_f64().unwrap(), a["range"][1].as_f64().unwrap());
        let p = a["predicted_seconds"].as_f64().unwrap();
        assert!(lo <= p && p <= hi, "{a}");
    }
    let v = &report["verify"];
    assert_eq!(v["method"], advice[0]["method"]);
    assert_eq!(v["reached"], true);
    assert!(v["estimated_rel_mse"].as_f64().unwrap() <= 1e-4);
}

#[test]
fn advise_refuses_bad_input() {
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_pathlab"))
            .arg("advise")
            .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml"))
            .args(args)
            .output()
            .unwrap();
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (code, err) = run(&["--target-rel-error", "-1"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("--target-rel-error"), "{err}");
    let (code, err) = run(&["--target-rel-error", "1e-3", "--methods", "nee-double-count"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("biased"), "{err}");
    let (code, _) = run(&[]);
    assert_eq!(code, Some(2), "a target is required (clap usage error)");
}
