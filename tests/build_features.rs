//! The Python extension's build reuses what `cargo test` built. `scripts/python_tests.sh` runs
//! `pip install ./python` after the suite, into the same `target/`; cargo reuses a crate only
//! where both builds resolve it to the same features (and the same for everything it depends
//! on), so a crate whose features differ compiles again, with every crate above it. The script
//! therefore builds the extension with its `viewer` feature (the library's viewer built in: its
//! eframe sets features of wgpu and its parts), and the library asks syn 3 for the features
//! pyo3's macros ask (a build-dependency, see Cargo.toml); otherwise CI compiled the library,
//! naga, wgpu, image, exr and serde a second time (265 s on a clean checkout, 57 units).
//!
//! Every crate the extension's build (with `viewer`) shares with the suite's must resolve, in
//! the extension's build, to feature sets the suite's build has too (`cargo tree` on the lock
//! file; on a fresh machine it downloads pyo3 and numpy, which `cargo test` does not need).
//! Without the build-dependency this fails on syn 3; without `viewer`, on wgpu and its parts.

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// Package (name and version) -> the feature sets it resolves to in `package`'s build with
/// `features` (host and target builds of one package may differ, so a set of them).
fn resolved(package: &str, features: &str, edges: &str) -> BTreeMap<String, BTreeSet<String>> {
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--locked", "--package", package, "--features", features, "--edges", edges, "--prefix", "none", "--format", "{p} [{f}]"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    assert!(out.status.success(), "cargo tree --package {package}: {}", String::from_utf8_lossy(&out.stderr));
    let mut packages: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let line = line.trim_end_matches(" (*)");
        let Some((id, features)) = line.rsplit_once(" [") else { continue };
        // A path package's `{p}` names its directory after the version: name and version only.
        let id = id.split(" (").next().unwrap_or(id).to_string();
        packages.entry(id).or_default().insert(features.trim_end_matches(']').to_string());
    }
    packages
}

#[test]
fn the_python_extension_resolves_the_crates_it_shares_with_the_suite_as_the_suite_does() {
    // What `cargo test` builds: the library, the CLI and the tests, dev-dependencies included.
    let suite = resolved("pathlab", "", "normal,build,dev");
    // As scripts/python_tests.sh builds it (MATURIN_PEP517_ARGS="--features viewer").
    let python = resolved("pathlab-python", "viewer", "normal,build");
    assert!(suite.keys().any(|id| id.starts_with("wgpu ")) && python.keys().any(|id| id.starts_with("pyo3 ")), "cargo tree listed no packages");
    let differ: Vec<String> = python
        .iter()
        .filter_map(|(id, sets)| {
            let theirs = suite.get(id)?;
            let missing: Vec<&String> = sets.difference(theirs).collect();
            (!missing.is_empty()).then(|| format!("{id}: the extension's build asks [{}], the suite's has {theirs:?}", missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("], [")))
        })
        .collect();
    assert!(differ.is_empty(), "crates that `pip install ./python` would compile a second time:\n{}", differ.join("\n"));
}
