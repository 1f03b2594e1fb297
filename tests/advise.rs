//! `pathlab advise` on the study scene ranks the methods as the study's equal-time table does
//! (efficiency best 590-770x plain, mis ~155x, nee ~80x, cosine ~2.3x: gaps of 2x or more between
//! neighbours, README "Reproducing the study"), and `--verify` renders the winner to the target.
//! The ranking comes from estimates, never from wall time alone; no time is asserted.

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
    let order: Vec<&str> = advice.iter().map(|a| a["method"].as_str().unwrap()).collect();
    println!("{}", serde_json::to_string_pretty(&report).unwrap());
    assert_eq!(order, ["best", "mis", "nee", "cosine", "plain"], "advise's ranking");
    for a in advice {
        assert!(a["predicted_seconds"].as_f64().is_some_and(|t| t > 0.0), "{a}");
        let (lo, hi) = (a["range"][0].as_f64().unwrap(), a["range"][1].as_f64().unwrap());
        let p = a["predicted_seconds"].as_f64().unwrap();
        assert!(lo <= p && p <= hi, "{a}");
    }
    assert!(advice[0]["speedup_vs_plain"].as_f64().unwrap() > 10.0);
    let v = &report["verify"];
    assert_eq!(v["method"], "best");
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
