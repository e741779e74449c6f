//! The file-format docs (docs/file-formats.md and the rustdoc of `sh::file` and
//! `brdf::dbrdf::file`) match the files brdfkit writes: compression, block layout (tiles
//! or scan lines), part names, channel names and sample types, read from the headers of
//! files written by this build; the light set's JSON keys and CSV header.

use exr::meta::attribute::SampleType;
use exr::meta::header::Header;
use exr::meta::BlockDescription;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn headers(path: &Path) -> Vec<Header> {
    exr::meta::MetaData::read_from_file(path, false)
        .unwrap()
        .headers
        .to_vec()
}

fn part_name(h: &Header) -> Option<String> {
    h.own_attributes.layer_name.as_ref().map(|n| n.to_string())
}

/// The encoding as the docs state it: "RLE compression, 64x64 tiles" or "ZIP16
/// compression, scan lines".
fn encoding(h: &Header) -> String {
    let blocks = match h.blocks {
        BlockDescription::ScanLines => "scan lines".to_string(),
        BlockDescription::Tiles(t) => format!("{}x{} tiles", t.tile_size.0, t.tile_size.1),
    };
    format!("{:?} compression, {blocks}", h.compression)
}

/// Channel names, each checked to be 32-bit float.
fn f32_channels(h: &Header) -> Vec<String> {
    h.channels
        .list
        .iter()
        .map(|c| {
            assert_eq!(c.sample_type, SampleType::F32, "{}", c.name);
            c.name.to_string()
        })
        .collect()
}

/// Markdown or a Rust module doc as one line of words (`//!` and line breaks removed).
fn words(text: &str) -> String {
    text.lines()
        .map(|l| l.trim_start().trim_start_matches("//!"))
        .collect::<Vec<_>>()
        .join(" ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The section of docs/file-formats.md under the `## ` heading starting with `title`.
fn section(doc: &str, title: &str) -> String {
    let start = doc
        .find(&format!("\n## {title}"))
        .unwrap_or_else(|| panic!("no section {title}"));
    let rest = &doc[start + 1..];
    let end = rest[3..].find("\n## ").map_or(rest.len(), |e| e + 3);
    words(&rest[..end])
}

/// The check: `text` states `encoding` with "Encoding: " before it, and no other encoding.
fn states_encoding(text: &str, encoding: &str) -> Result<(), String> {
    if !text.contains(&format!("Encoding: {encoding}")) {
        return Err(format!("does not state 'Encoding: {encoding}'"));
    }
    for other in ["ZIP", "scan lines", "PIZ", "uncompressed"] {
        if text.contains(other) && !encoding.contains(other) {
            return Err(format!("also says '{other}'"));
        }
    }
    Ok(())
}

/// Files written by this build: an SH data set with a basis table, a D-BRDF, a render.
fn written(dir: &Path) {
    let mut ds =
        brdfkit::sh::read_sh_dataset(&root().join("golden/magenta-plastic-5b-8x4.exr")).unwrap();
    ds.set_basis_table(Some(
        brdfkit::sh::dataset::ShBasisTable::tabulate(8, 4, ds.bands()).unwrap(),
    ))
    .unwrap();
    brdfkit::sh::file::write_sh_dataset(&dir.join("sh.exr"), &ds).unwrap();
    let (db, _) =
        brdfkit::brdf::dbrdf::file::read_dbrdf(&root().join("golden/lindt-paper-16x8.exr"))
            .unwrap();
    brdfkit::brdf::dbrdf::file::write_dbrdf(&dir.join("d.exr"), &db, "test").unwrap();
    brdfkit::image_io::write_exr(&dir.join("r.exr"), &brdfkit::image_io::Image::new(5, 3)).unwrap();
}

#[test]
fn the_docs_state_the_written_exr_layouts() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    written(p);
    let doc = std::fs::read_to_string(root().join("docs/file-formats.md")).unwrap();
    let sh_doc = words(&std::fs::read_to_string(root().join("src/sh/file/mod.rs")).unwrap());
    let db_doc = words(&std::fs::read_to_string(root().join("src/brdf/dbrdf/file.rs")).unwrap());

    // Rendered images: one unnamed part, R, G, B.
    let r = headers(&p.join("r.exr"));
    assert_eq!(r.len(), 1);
    assert_eq!(part_name(&r[0]), None);
    assert_eq!(f32_channels(&r[0]), ["B", "G", "R"]);
    let render_doc = section(&doc, "Rendered images");
    states_encoding(&render_doc, &encoding(&r[0])).unwrap();
    assert!(render_doc.contains("Channels `R`, `G`, `B` (stored sorted by name"));

    // SH data sets: parts sh-coefficients and sh-basis, channel names as documented.
    let sh = headers(&p.join("sh.exr"));
    let names: Vec<_> = sh.iter().map(part_name).collect();
    assert_eq!(
        names,
        [Some("sh-coefficients".into()), Some("sh-basis".into())]
    );
    let sh_section = section(&doc, "SH data sets");
    for h in &sh {
        states_encoding(&sh_section, &encoding(h)).unwrap();
        states_encoding(&sh_doc, &encoding(h)).unwrap();
        assert!(sh_section.contains(&format!("`{}`", part_name(h).unwrap())));
    }
    let bands = 5;
    let coeff = f32_channels(&sh[0]);
    assert_eq!(coeff.len(), 3 * bands * bands);
    for c in &coeff {
        // c.l{l}.m{m}.{R|G|B}
        let f: Vec<&str> = c.split('.').collect();
        assert_eq!(f.len(), 4, "{c}");
        assert_eq!(f[0], "c");
        let l: i32 = f[1].strip_prefix('l').unwrap().parse().unwrap();
        let m: i32 = f[2].strip_prefix('m').unwrap().parse().unwrap();
        assert!(l < bands as i32 && m.abs() <= l, "{c}");
        assert!(["R", "G", "B"].contains(&f[3]), "{c}");
    }
    assert!(sh_section.contains("`c.l{l}.m{m}.{R|G|B}`") && sh_doc.contains("c.l{l}.m{m}.{R|G|B}"));
    let basis = f32_channels(&sh[1]);
    assert_eq!(basis.len(), bands * bands);
    assert!(basis.iter().all(|c| c.starts_with("Y.l")));
    assert!(sh_section.contains("`Y.l{l}.m{m}`"));

    // D-BRDF files: one part dbrdf-p, one channel p.
    let db = headers(&p.join("d.exr"));
    assert_eq!(db.len(), 1);
    assert_eq!(part_name(&db[0]).as_deref(), Some("dbrdf-p"));
    assert_eq!(f32_channels(&db[0]), ["p"]);
    let db_section = section(&doc, "D-BRDF files");
    states_encoding(&db_section, &encoding(&db[0])).unwrap();
    states_encoding(&db_doc, &encoding(&db[0])).unwrap();
    assert!(db_section.contains("named `dbrdf-p`, one 32-bit float channel `p`"));
}

#[test]
fn the_encoding_check_rejects_the_old_statement() {
    // Seeded fault: the sentence the SH and D-BRDF docs carried before they were corrected
    // to match the written files, against the encoding this build writes.
    let d = tempfile::tempdir().unwrap();
    written(d.path());
    let e = encoding(&headers(&d.path().join("sh.exr"))[0]);
    let old = "OpenEXR, 32-bit float channels, lossless compression (ZIP), scan lines.";
    assert!(states_encoding(old, &e).is_err());
    let both = format!("Encoding: {e}. {old}");
    assert!(
        states_encoding(&both, &e).is_err(),
        "a stale second statement"
    );
}

#[test]
fn the_docs_state_the_light_set_keys_and_csv_header() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let mut ls = brdfkit::env::LightSet::default();
    ls.push(glam::DVec3::Y, glam::DVec3::new(1.0, 2.0, 3.0));
    let header = brdfkit::env::lightset::file::LightSetHeader {
        sampler: "median-cut".into(),
        n: 1,
        seed: None,
        probe_file: None,
        total_irradiance: [1.0, 2.0, 3.0],
    };
    brdfkit::env::lightset::file::write_json(&p.join("l.json"), &header, &ls).unwrap();
    brdfkit::env::lightset::file::write_csv(&p.join("l.csv"), &ls).unwrap();
    let doc = std::fs::read_to_string(root().join("docs/file-formats.md")).unwrap();
    let s = section(&doc, "Light sets");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(p.join("l.json")).unwrap()).unwrap();
    let obj = v.as_object().unwrap();
    let mut keys: Vec<_> = obj.keys().cloned().collect();
    keys.sort();
    assert_eq!(keys, ["format", "header", "lights", "version"]);
    for group in ["header", "lights"] {
        for k in obj[group].as_object().unwrap().keys() {
            assert!(
                s.contains(&format!("`{k}`")),
                "{group}.{k} is not documented"
            );
        }
    }
    assert!(s.contains(&format!("`format` (`{}`)", obj["format"])));
    assert!(s.contains(&format!("`version` ({})", obj["version"])));
    let csv = std::fs::read_to_string(p.join("l.csv")).unwrap();
    let first = csv.lines().next().unwrap();
    assert!(s.contains(&format!("the header line `{first}`")), "{first}");
}
