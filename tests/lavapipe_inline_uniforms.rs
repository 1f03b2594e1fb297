//! A heap overflow in lavapipe (Mesa 22.3.6, the driver of Debian 12 and of CI) that the
//! kernels must not trigger. Making a compute pipeline, lavapipe looks for branches that read
//! nothing but uniform buffers at constant offsets (`lvp_find_inlinable_uniforms`), to compile
//! variants with those values inlined. It records each offset in a table of 4 entries per
//! buffer, `uniform_offsets[32][4]`, but writes entry k of buffer b at `b * 32 + k`: within the
//! table for buffers 1 to 3 (0 is the push constants), past its end from the fourth on. The
//! path tracer has eight uniform buffers; with an orthographic camera the unrolled triangle
//! tests of camera rays, which all share one direction, branched on the eighth
//! (`small_vertices`) alone, and the suite aborted at random ("corrupted double-linked list",
//! about one process in twenty) while the orthographic fixture's test ran (README, "Tests");
//! under the Halton samplers the radical inverse's digit loops, which divide by the dimension's
//! prime, read the fifth (`halton_primes`) at constant offsets and wrote past it too.
//!
//! The check watches that store. The study scene's pipelines (every preset and sampler) and each
//! fixture scene's (`mis`) are made in a child
//! process (this binary's ignored `child_makes_pipelines`, no dispatch) under gdb, with a
//! breakpoint on the store's instruction, found in libvulkan_lvp.so by its bytes; every index
//! written must stay inside the table (< 128), and the breakpoint must have been hit (the
//! routine ran, so the check saw something). Where the driver is another build, or gdb is
//! missing, the test says NOT RUN.

use crate::common;

use std::path::{Path, PathBuf};

/// The routine's last instructions, ending with the store (Mesa 22.3.6, Debian 12): `test r15,
/// r15; je; cmp r8b, 4; je; add r8d, 1; mov [r9], r8b; mov [r12 + rsi * 4], edi`.
const STORE_SIGNATURE: [u8; 26] = [
    0x4d, 0x85, 0xff, 0x74, 0x0a, 0x41, 0x80, 0xf8, 0x04, 0x0f, 0x84, 0xe8, 0xfe, 0xff, 0xff, 0x41, 0x83, 0xc0, 0x01, 0x45, 0x88, 0x01, 0x41, 0x89, 0x3c, 0xb4,
];

/// The table's entries: 32 buffers times 4 offsets.
const TABLE_ENTRIES: u64 = 128;

const CHILD_SCENES: &str = "PATHLAB_CHILD_PIPELINE_SCENES";

/// The path tracer's pipeline (`mis`; every preset and sampler for the first scene, the study
/// scene) of each scene listed in PATHLAB_CHILD_PIPELINE_SCENES, made and dropped; run by the
/// test below.
#[test]
#[ignore = "run by lavapipe_inline_uniforms_stay_in_their_table, in a child process under gdb"]
fn child_makes_pipelines() {
    let Ok(list) = std::env::var(CHILD_SCENES) else {
        return common::not_run("child_makes_pipelines", "run alone it has no scenes: lavapipe_inline_uniforms_stay_in_their_table runs it");
    };
    let gpu = pathlab::gpu::Gpu::new(None).unwrap();
    let pipelines = pathlab::gpu::PathTracerPipelines::new(&gpu);
    for (k, path) in list.lines().enumerate() {
        let scene = pathlab::scene::Scene::load(path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let methods: Vec<pathlab::method::Method> = if k == 0 {
            let presets = pathlab::method::Preset::ALL.map(|p| p.method());
            let samplers = pathlab::method::Sampler::ALL.map(|sampler| pathlab::method::Method { sampler, ..pathlab::method::Preset::Mis.method() });
            presets.into_iter().chain(samplers).collect()
        } else {
            vec![pathlab::method::Preset::Mis.method()]
        };
        for method in methods {
            let m = method.name();
            if pathlab::render::Renderer::new(&gpu, &pipelines, &scene, method, 1).is_ok() {
                println!("SCENE {path} {m}");
            }
        }
    }
}

/// The gdb script: a breakpoint on the store (at the lowest mapping of libvulkan_lvp.so plus
/// the signature's end, its bytes checked there) that prints each index written, without
/// stopping.
fn gdb_script(store_offset: u64) -> String {
    format!(
        r#"set pagination off
set confirm off
python
import gdb
armed = []
class Store(gdb.Breakpoint):
    def stop(self):
        print("STORE %d" % (int(gdb.parse_and_eval("$rsi")) & 0xffffffff))
        return False
def on_load(event):
    name = event.new_objfile.filename or ""
    if "libvulkan_lvp" in name and not armed:
        maps = open("/proc/%d/maps" % gdb.selected_inferior().pid).read().splitlines()
        base = min(int(l.split("-")[0], 16) for l in maps if "libvulkan_lvp" in l)
        address = base + {store_offset}
        code = bytes(gdb.selected_inferior().read_memory(address, 4))
        print("ARMED %s" % code.hex())
        Store("*%#x" % address)
        armed.append(address)
gdb.events.new_objfile.connect(on_load)
end
run
"#
    )
}

#[test]
fn lavapipe_inline_uniforms_stay_in_their_table() {
    let test = "lavapipe_inline_uniforms_stay_in_their_table";
    // The driver this process loaded, found through its mappings once a device exists.
    let _ = common::gpu();
    let maps = std::fs::read_to_string("/proc/self/maps").unwrap_or_default();
    let Some(library) = maps.lines().filter_map(|l| l.split_whitespace().nth(5)).find(|p| p.contains("libvulkan_lvp")).map(PathBuf::from) else {
        return common::not_run(test, "the adapter is not lavapipe (the overflow is lavapipe's)");
    };
    let bytes = std::fs::read(&library).unwrap();
    let found: Vec<usize> = bytes.windows(STORE_SIGNATURE.len()).enumerate().filter(|(_, w)| *w == STORE_SIGNATURE).map(|(i, _)| i).collect();
    let [start] = found[..] else {
        let why = format!("{} is not Mesa 22.3.6's build: the store's bytes occur {} times", library.display(), found.len());
        return common::not_run(test, &why);
    };
    if std::process::Command::new("gdb").arg("--version").output().is_err() {
        return common::not_run(test, "gdb is not installed (apt-get install gdb)");
    }
    // The store's instruction: the signature's last 4 bytes (file offsets are the library's
    // virtual addresses here: its segments are mapped at their file offsets; the script checks
    // the bytes it finds there).
    let store_offset = (start + STORE_SIGNATURE.len() - 4) as u64;
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(&fixtures)
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).into_iter().flatten())
        .map(|f| f.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .collect();
    scenes.sort();
    // The study scene first (every preset and sampler: the Halton primes' buffer, the fifth,
    // overflowed under the Halton samplers), then the fixtures (the orthographic one overflowed
    // on the eighth, `small_vertices`).
    scenes.insert(0, Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml"));
    let list: Vec<String> = scenes.iter().map(|p| p.display().to_string()).collect();
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("store.gdb");
    std::fs::write(&script, gdb_script(store_offset)).unwrap();
    let run = std::process::Command::new("gdb")
        .args(["-q", "-batch", "-x"])
        .arg(&script)
        .arg("--args")
        .arg(std::env::current_exe().unwrap())
        .args(["lavapipe_inline_uniforms::child_makes_pipelines", "--exact", "--ignored", "--test-threads=1", "--nocapture"])
        .env(CHILD_SCENES, list.join("\n"))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success() && out.contains("test result: ok"), "the child failed: {:?}\n{out}\n{}", run.status, String::from_utf8_lossy(&run.stderr));
    assert!(out.contains("ARMED 41893cb4"), "the breakpoint is not on the store:\n{out}");
    // Per scene (and method), the indices written while its pipeline was made.
    let mut writes: Vec<(String, Vec<u64>)> = Vec::new();
    let mut pending = Vec::new();
    for line in out.lines() {
        if let Some(i) = line.strip_prefix("STORE ") {
            pending.push(i.trim().parse::<u64>().unwrap());
        } else if let Some(scene) = line.strip_prefix("SCENE ") {
            writes.push((scene.to_string(), std::mem::take(&mut pending)));
        }
    }
    let first_scene = pathlab::method::Preset::ALL.len() + pathlab::method::Sampler::ALL.len();
    assert_eq!(writes.len(), scenes.len() - 1 + first_scene, "a pipeline was not made:\n{out}");
    let total: usize = writes.iter().map(|(_, w)| w.len()).sum();
    println!("{} pipelines, {total} offsets recorded, largest index {}", writes.len(), writes.iter().flat_map(|(_, w)| w).max().unwrap_or(&0));
    assert!(total > 0, "the breakpoint was never hit: the check saw nothing\n{out}");
    let past: Vec<String> = writes
        .iter()
        .filter(|(_, w)| w.iter().any(|&i| i >= TABLE_ENTRIES))
        .map(|(scene, w)| format!("{scene}: indices {w:?} (buffer = index / 32)"))
        .collect();
    assert!(past.is_empty(), "lavapipe wrote past its table of inlinable uniforms (entries {TABLE_ENTRIES}):\n{}", past.join("\n"));
}
