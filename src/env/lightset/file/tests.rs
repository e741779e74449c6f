use super::*;
use crate::env::{Probe, SamplerConfig};

fn sample_set() -> LightSet {
    let t: Vec<[f32; 3]> = (0..32)
        .map(|i| [i as f32 * 0.37, 1.0 / (1.0 + i as f32), 0.1])
        .collect();
    let (p, _) = Probe::from_texels("io", 8, 4, t, &Default::default()).unwrap();
    SamplerConfig::MedianCut { n: 7 }.run(&p)
}

#[test]
fn json_and_csv_round_trip_bit_exact() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let ls = sample_set();
    let cfg = SamplerConfig::MedianCut { n: 7 };
    let h = LightSetHeader::new(&cfg, Some("io.exr"), &ls);
    write_json(&d.join("a.json"), &h, &ls).unwrap();
    let (h2, ls2) = read_json(&d.join("a.json")).unwrap();
    assert_eq!((h2, &ls2), (h, &ls));
    write_csv(&d.join("a.csv"), &ls).unwrap();
    assert_eq!(read_csv(&d.join("a.csv")).unwrap(), ls);
    // No temporary files left behind.
    let names: Vec<_> = std::fs::read_dir(d).unwrap().collect();
    assert_eq!(names.len(), 2);
}

#[test]
fn csv_errors_name_file_line_and_field() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let p = d.join("bad.csv");
    std::fs::write(&p, format!("{CSV_HEADER}\n0,1,0,1,1,1\n0,1,0,1,x,1\n")).unwrap();
    let e = read_csv(&p).unwrap_err().to_string();
    assert!(
        e.contains("bad.csv:3") && e.contains("irradiance_g"),
        "message: {e}"
    );
    std::fs::write(&p, format!("{CSV_HEADER}\n0,1,0,1,1\n")).unwrap();
    let e = read_csv(&p).unwrap_err().to_string();
    assert!(e.contains("bad.csv:2") && e.contains("6 fields"), "{e}");
    std::fs::write(&p, "x,y\n").unwrap();
    assert!(read_csv(&p).unwrap_err().to_string().contains("header"));
    std::fs::write(&p, format!("{CSV_HEADER}\n0,2,0,1,1,1\n")).unwrap();
    let e = read_csv(&p).unwrap_err().to_string();
    assert!(e.contains("light 0") && e.contains("length"), "{e}");
    std::fs::write(&p, format!("{CSV_HEADER}\n0,1,0,1,-1,1\n")).unwrap();
    assert!(read_csv(&p).unwrap_err().to_string().contains("negative"));
    std::fs::write(&p, format!("{CSV_HEADER_V0}\n0,1,0,1,x,1\n")).unwrap();
    let e = read_csv(&p).unwrap_err().to_string();
    assert!(
        e.contains("bad.csv:2") && e.contains("field power_g"),
        "{e}"
    );
    let j = d.join("bad.json");
    std::fs::write(&j, "{\"format\": 3").unwrap();
    let e = read_json(&j).unwrap_err().to_string();
    assert!(e.contains("bad.json") && e.contains("line"), "{e}");
}

/// Files written before the rename (`power_*` keys and columns, header `total_power`)
/// read as the same lights; what is written uses only the new names.
#[test]
fn former_power_names_are_read_new_names_written() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let mut want = LightSet::default();
    want.push(glam::DVec3::Y, glam::DVec3::new(1.5, 0.25, 2.0));
    want.push(glam::DVec3::X, glam::DVec3::new(0.0, 3.0, 0.125));
    let old_json = r#"{"format": "brdfkit-lightset", "version": 1,
        "header": {"sampler": "median-cut", "n": 2, "seed": null, "probe_file": null,
                   "total_power": [1.5, 3.25, 2.125]},
        "lights": {"dir_x": [0, 1], "dir_y": [1, 0], "dir_z": [0, 0],
                   "power_r": [1.5, 0], "power_g": [0.25, 3], "power_b": [2, 0.125]}}"#;
    std::fs::write(d.join("old.json"), old_json).unwrap();
    let (h, ls) = read_json(&d.join("old.json")).unwrap();
    assert_eq!(ls, want);
    assert_eq!(h.total_irradiance, [1.5, 3.25, 2.125]);
    std::fs::write(
        d.join("old.csv"),
        "dir_x,dir_y,dir_z,power_r,power_g,power_b\n0,1,0,1.5,0.25,2\n1,0,0,0,3,0.125\n",
    )
    .unwrap();
    assert_eq!(read_csv(&d.join("old.csv")).unwrap(), want);

    let cfg = SamplerConfig::MedianCut { n: 2 };
    write_json(
        &d.join("new.json"),
        &LightSetHeader::new(&cfg, None, &want),
        &want,
    )
    .unwrap();
    write_csv(&d.join("new.csv"), &want).unwrap();
    for f in ["new.json", "new.csv"] {
        let text = std::fs::read_to_string(d.join(f)).unwrap();
        assert!(
            text.contains("irradiance_r") && !text.contains("power"),
            "{f}: {text}"
        );
    }
    assert_eq!(read_json(&d.join("new.json")).unwrap().1, want);
    assert_eq!(read_csv(&d.join("new.csv")).unwrap(), want);
}
