//! The `deploy/` recipes: the Slurm job array runs for real on a one-node cluster (started and
//! stopped by `tests/slurm/single_node_cluster.sh`), and its merged image equals a single run;
//! the Kubernetes manifests parse as Indexed Jobs whose completion index selects the shard.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use pathlab::output::read_exr;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn yaml(path: &str) -> yaml_rust2::Yaml {
    let text = std::fs::read_to_string(root().join(path)).unwrap();
    let mut docs = yaml_rust2::YamlLoader::load_from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    assert_eq!(docs.len(), 1, "{path}: one document");
    docs.remove(0)
}

#[test]
fn kubernetes_manifests_are_indexed_jobs_mapping_the_index_to_the_shard() {
    let job = yaml("deploy/kubernetes/render-indexed-job.yaml");
    assert_eq!(job["apiVersion"].as_str(), Some("batch/v1"));
    assert_eq!(job["kind"].as_str(), Some("Job"));
    let spec = &job["spec"];
    assert_eq!(spec["completionMode"].as_str(), Some("Indexed"));
    let completions = spec["completions"].as_i64().expect("completions");
    let container = &spec["template"]["spec"]["containers"][0];
    let args: String = container["args"].as_vec().unwrap().iter().map(|a| a.as_str().unwrap().to_string()).collect::<Vec<_>>().join(" ");
    assert!(args.contains(&format!("--shard \"${{JOB_COMPLETION_INDEX}}/{completions}\"")), "index -> shard: {args}");
    assert!(args.contains("part-${JOB_COMPLETION_INDEX}.exr"), "{args}");
    assert_eq!(spec["template"]["spec"]["restartPolicy"].as_str(), Some("Never"));
    let merge = yaml("deploy/kubernetes/merge-job.yaml");
    assert_eq!(merge["kind"].as_str(), Some("Job"));
    let margs = merge["spec"]["template"]["spec"]["containers"][0]["args"][0].as_str().unwrap();
    assert!(margs.starts_with("pathlab merge /data/parts/part-*.exr"), "{margs}");
}

/// Stops the test cluster however the test ends.
struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(root().join("tests/slurm/single_node_cluster.sh")).arg("stop").arg(&self.0).status();
    }
}

#[test]
fn slurm_job_array_and_merge_equal_a_single_run() {
    if Command::new("sbatch").arg("--version").output().is_err() {
        // CI installs slurm-wlm (.ci/run); elsewhere the test says why it did not run.
        assert!(std::env::var("CI").is_err(), "CI must have Slurm: .ci/run installs slurm-wlm and munge");
        common::not_run("slurm_job_array_and_merge_equal_a_single_run", "Slurm is not installed (sudo apt-get install slurm-wlm munge)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_path_buf();
    let cluster_dir = d.join("cluster");
    let start = Command::new(root().join("tests/slurm/single_node_cluster.sh")).arg("start").arg(&cluster_dir).output().unwrap();
    let _cluster = Cluster(cluster_dir.clone());
    println!("{}{}", String::from_utf8_lossy(&start.stdout), String::from_utf8_lossy(&start.stderr));
    assert!(start.status.success(), "the cluster did not start");

    let scene = root().join("assets/scenes/study.toml");
    let render_flags = ["--width", "128", "--height", "64", "--method", "mis", "--seed", "11"];
    let submit = Command::new(root().join("deploy/slurm/submit.sh"))
        .current_dir(&d)
        .env("SLURM_CONF", cluster_dir.join("slurm.conf"))
        .env("PATHLAB", env!("CARGO_BIN_EXE_pathlab"))
        .env("WAIT", "1")
        .arg(&scene)
        .arg("256")
        .arg("4")
        .arg(d.join("parts"))
        .arg(d.join("merged.exr"))
        .args(render_flags)
        .output()
        .unwrap();
    let log = |pattern: &str| -> String {
        std::fs::read_dir(&d)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with(pattern))
            .map(|e| format!("--- {}\n{}", e.file_name().to_string_lossy(), std::fs::read_to_string(e.path()).unwrap_or_default()))
            .collect()
    };
    println!("{}{}", String::from_utf8_lossy(&submit.stdout), String::from_utf8_lossy(&submit.stderr));
    println!("{}{}", log("pathlab-shard-"), log("pathlab-merge-"));
    assert!(submit.status.success(), "the job array or its merge failed");
    let parts: Vec<_> = std::fs::read_dir(d.join("parts")).unwrap().flatten().collect();
    assert_eq!(parts.len(), 4, "one part per array task");

    let single = d.join("single.exr");
    let o = Command::new(env!("CARGO_BIN_EXE_pathlab"))
        .arg("render")
        .arg(&scene)
        .args(render_flags)
        .args(["--spp", "256", "--variance", "--quiet", "-o"])
        .arg(&single)
        .output()
        .unwrap();
    assert!(o.status.success());
    let (merged, _) = read_exr(&d.join("merged.exr")).unwrap();
    let (one, _) = read_exr(&single).unwrap();
    assert_eq!(merged.spp, 256);
    let max_rel = merged
        .mean
        .iter()
        .flatten()
        .zip(one.mean.iter().flatten())
        .map(|(&a, &b)| (a as f64 - b as f64).abs() / (b as f64).abs().max(1e-3))
        .fold(0.0, f64::max);
    println!("Slurm: 4 shards merged against a single 256-spp run: max relative pixel difference {max_rel:.2e}");
    assert!(max_rel <= 2e-6, "merged differs from the single run by {max_rel:.2e}");
}
