//! `brdfkit golden list`: every manifest entry, one line each for scripts (name, scene
//! file, FLIP bounds, the bounds a GPU build is held to, AOV), and the same as JSON.

use std::path::Path;

use crate::common;

/// The manifest's entry names, in order, read from its text (not through the crate).
fn manifest_names(golden: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(golden.join("manifest.toml")).unwrap();
    let names: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix("name = \""))
        .map(|l| l.trim_end_matches('"').to_string())
        .collect();
    assert_eq!(names.len(), text.matches("[[entry]]").count());
    names
}

#[test]
fn golden_list_lists_every_manifest_entry() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let names = manifest_names(&golden);
    assert!(names.len() > 20, "{names:?}");
    let d = tempfile::tempdir().unwrap();
    let dir = golden.to_str().unwrap();
    let r = common::brdfkit(d.path()).run(&["golden", "list", "--dir", dir]);
    assert!(r.success(), "{}{}", r.stdout, r.stderr);
    let rows: Vec<Vec<&str>> = r.stdout.lines().map(|l| l.split('\t').collect()).collect();
    let listed: Vec<&str> = rows.iter().map(|f| f[0]).collect();
    assert_eq!(
        listed, names,
        "one line per entry, in manifest order:\n{}",
        r.stdout
    );
    for f in &rows {
        assert_eq!(f.len(), 5, "name, scene, bounds, GPU bounds, AOV: {f:?}");
        assert!(Path::new(f[1]).is_file(), "scene file {}", f[1]);
        assert!(
            f[2].starts_with("mean=") && f[3].starts_with("mean="),
            "{f:?}"
        );
    }
    let row = |name: &str| rows.iter().find(|f| f[0] == name).unwrap();
    assert_eq!(row("debug-normal")[4], "normal");
    assert_eq!(row("default-160x120")[4], "-");
    // gpu-bounds.toml's entries carry its bounds in the GPU column, the others the manifest's.
    let fabric = row("fig3-9-blue-synthetic-fabric-median-cut");
    assert_eq!(
        (fabric[2], fabric[3]),
        ("mean=0.01,p99=0.1", "mean=0.004,p99=0.04")
    );
    assert_eq!(row("fig3-13-teal-paint")[3], "mean=0.01,p99=0.1");

    let r = common::brdfkit(d.path()).run(&["golden", "list", "--dir", dir, "--json"]);
    assert!(r.success(), "{}", r.stderr);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    let entries = v["entries"].as_array().unwrap();
    let json_names: Vec<&str> = entries
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(json_names, names);
    let fabric = entries
        .iter()
        .find(|e| e["name"] == "fig3-9-blue-synthetic-fabric-median-cut")
        .unwrap();
    assert_eq!(fabric["gpu_bounds"]["flip_mean"], 0.004);
    assert_eq!(fabric["gpu_side"], true);
    assert_eq!(fabric["aov"], serde_json::Value::Null);
}
