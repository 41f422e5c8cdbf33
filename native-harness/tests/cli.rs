//! The `meshflow` binary on the bundled real meshes, as a user runs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures")
        .join(name)
}

fn meshflow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshflow"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// A fresh, empty folder under the system's temporary folder for one test, named
/// `meshflow-{tag}-` and a random suffix; removed with everything in it when the returned guard
/// drops, whether the test passes or panics (keep the guard in scope: `let dir =
/// temp_dir("x"); let dir = dir.path();`).
fn temp_dir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("meshflow-cli-{tag}-"))
        .tempdir()
        .expect("a temporary folder")
}

#[test]
fn inspect_reports_every_fixture() {
    for name in [
        "meshes/stone_lantern.obj",
        "meshes/bread.obj",
        "meshes/garden_lantern.obj",
        "meshes/deck_chair.obj",
        "meshes/finger_lower_link.stl",
        "meshes/solo_lower_leg.obj",
        "meshes/humanoid_box_ascii.stl",
        "points/stone_lantern_2048.ply",
    ] {
        let report = json(&meshflow(&[
            "inspect",
            fixture(name).to_str().unwrap(),
            "--json",
        ]));
        assert!(report["vertices"].as_u64().unwrap() > 0, "{name}");
        let t = &report["topology"];
        assert_eq!(t["faces"], report["faces"], "{name}");
        if name.starts_with("points/") {
            assert_eq!(report["point_cloud"], true);
            assert_eq!(report["vertices"], 2048);
        }
    }
    // Counts recorded in tests/fixtures/meshes/SOURCES.md.
    let lantern = json(&meshflow(&[
        "inspect",
        fixture("meshes/stone_lantern.obj").to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(
        (lantern["vertices"].as_u64(), lantern["faces"].as_u64()),
        (Some(356), Some(736))
    );
    assert_eq!(lantern["topology"]["boundary_edges"], 0);
}

#[test]
fn extract_round_trip_keeps_every_face_of_clean_meshes() {
    for name in [
        "meshes/stone_lantern.obj",
        "meshes/finger_lower_link.stl",
        "meshes/humanoid_box_ascii.stl",
    ] {
        let r = json(&meshflow(&[
            "extract",
            fixture(name).to_str().unwrap(),
            "--extraction",
            "paper",
            "--json",
        ]));
        assert_eq!(r["lost_faces"], 0, "{name}: {r}");
        assert_eq!(r["flipped_faces"], 0, "{name}: {r}");
    }
    // The default manifold method never leaves a non-manifold or inconsistently wound edge.
    // Where the mesh's own adjacency has 3-cliques that are not faces (the stone lantern's
    // 4, which Algorithm 1 adds and which give it 12 non-manifold edges) it may take one in
    // place of a real face; elsewhere it gives every face back, wound as it was.
    for name in [
        "meshes/stone_lantern.obj",
        "meshes/finger_lower_link.stl",
        "meshes/bread.obj",
        "meshes/garden_lantern.obj",
    ] {
        let r = json(&meshflow(&[
            "extract",
            fixture(name).to_str().unwrap(),
            "--json",
        ]));
        let t = &r["topology_after"];
        assert_eq!(t["non_manifold_edges"], 0, "{name}: {r}");
        assert_eq!(t["inconsistent_winding_edges"], 0, "{name}: {r}");
        assert_eq!(r["flipped_faces"], 0, "{name}: {r}");
        if !name.contains("stone") {
            assert_eq!(r["lost_faces"], 0, "{name}: {r}");
        }
    }
    // The open, multi-part deck chair keeps its faces too; its boundary is what it is.
    let dir = temp_dir("extract");
    let dir = dir.path();
    let out = dir.join("chair.glb");
    let r = json(&meshflow(&[
        "extract",
        fixture("meshes/deck_chair.obj").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--max-hole-edges",
        "0",
        "--extraction",
        "paper",
        "--json",
    ]));
    assert_eq!(r["lost_faces"], 0, "{r}");
    assert_eq!(r["extract"]["hole_faces"], 0);
    assert!(std::fs::metadata(&out).unwrap().len() > 0);
}

#[test]
fn sample_convert_compare_pipeline() {
    let dir = temp_dir("pipeline");
    let dir = dir.path();
    let mesh = fixture("meshes/bread.obj");
    let points = dir.join("points.ply");
    let out = meshflow(&[
        "sample",
        mesh.to_str().unwrap(),
        "-n",
        "1000",
        "-o",
        points.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let cloud = json(&meshflow(&["inspect", points.to_str().unwrap(), "--json"]));
    assert_eq!(
        (cloud["vertices"].as_u64(), cloud["point_cloud"].as_bool()),
        (Some(1000), Some(true))
    );

    let glb = dir.join("bread.glb");
    assert!(
        meshflow(&["convert", mesh.to_str().unwrap(), glb.to_str().unwrap()])
            .status
            .success()
    );
    let same = json(&meshflow(&[
        "compare",
        glb.to_str().unwrap(),
        mesh.to_str().unwrap(),
        "--json",
    ]));
    let cube = fixture("meshes/humanoid_box_ascii.stl");
    let other = json(&meshflow(&[
        "compare",
        cube.to_str().unwrap(),
        mesh.to_str().unwrap(),
        "--json",
    ]));
    let cd = |v: &serde_json::Value| v["chamfer_x100"].as_f64().unwrap();
    // The same surface scores only sampling noise; a cube against the bread scores far worse.
    assert!(
        cd(&same) < 2.0 && cd(&other) > 3.0 * cd(&same),
        "{} vs {}",
        cd(&same),
        cd(&other)
    );
    assert_eq!(same["pred_topology"], same["gt_topology"]);
}

#[test]
fn bad_input_is_one_line_and_status_2() {
    let dir = temp_dir("bad");
    let dir = dir.path();
    let cases: [(&str, &[u8]); 4] = [
        ("truncated.stl", &[0u8; 90]),
        ("nan.obj", b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"),
        ("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
        ("empty.ply", b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"),
    ];
    for (name, bytes) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        for cmd in ["inspect", "extract"] {
            let out = meshflow(&[cmd, path.to_str().unwrap()]);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{cmd} {name}: {stderr}");
            assert!(
                stderr.starts_with("error: ") && stderr.trim_end().lines().count() == 1,
                "{stderr}"
            );
            assert!(!stderr.contains("panicked"), "{stderr}");
        }
    }
    let missing = meshflow(&["inspect", dir.join("does-not-exist.obj").to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(
        stderr.matches("No such file").count(),
        1,
        "the cause is printed once: {stderr}"
    );
    let bread = fixture("meshes/bread.obj");
    let bread = bread.to_str().unwrap();
    for args in [
        &["sample", bread, "-n", "0", "-o", "x.ply"][..],
        &["sample", bread, "-n", "99999999999", "-o", "x.ply"],
        &["compare", bread, bread, "--samples", "99999999999"],
        &["convert", bread, "x.fbx"],
    ] {
        let out = meshflow(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    }
    let points = fixture("points/stone_lantern_2048.ply");
    let out = meshflow(&[
        "sample",
        points.to_str().unwrap(),
        "-o",
        dir.join("x.ply").to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "sampling a point cloud is bad input"
    );
}

/// `meshflow ... | head`: the reader is gone before the first line.
#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    let bread = fixture("meshes/bread.obj");
    let bread = bread.to_str().unwrap();
    for args in [
        &["inspect", bread][..],
        &["compare", bread, bread, "--samples", "500"],
    ] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = Command::new(env!("CARGO_BIN_EXE_meshflow"))
            .args(args)
            .stdout(writer)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!stderr.contains("Broken pipe"), "{args:?}: {stderr}");
        #[cfg(unix)]
        {
            use std::os::unix::process::ExitStatusExt;
            assert_eq!(
                out.status.signal(),
                Some(13),
                "{args:?}: SIGPIPE, as `head` expects"
            );
        }
    }
}

fn golden_dir() -> PathBuf {
    std::env::var_os("MESHFLOW_GOLDEN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/golden"))
}

#[test]
fn verify_reproduces_the_golden_vectors_on_the_cpu() {
    let out = meshflow(&["verify", "--golden", golden_dir().to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("all tensors within"), "{stdout}");
    assert!(!stdout.contains("FAIL"), "{stdout}");
}

/// A few-second VAE configuration over the fixture dataset (meshes of <= 512 vertices).
const SMALL_TRAINING: &str = r#"{
  "model": {"num_vertices": 512, "num_latents": 128, "latent_dim": 8, "width_encoder": 32,
            "width_decoder": 32, "num_heads": 2, "num_layers_encoder": 1,
            "num_layers_decoder": 1, "max_degree": 16, "num_freqs": 4, "edge_dim": 32,
            "tau": 0.6, "length_buckets": true},
  "batch_size": 2, "steps": 4, "learning_rate": 0.001, "warmup_steps": 1,
  "final_lr_ratio": 0.1, "weight_decay": 0.0, "grad_clip": 1.0, "kl_weight": 0.001,
  "lambda_neg": 0.01, "position_weight": 10.0, "normal_weight": 1.0, "ema_decay": 0.9,
  "seed": 3, "checkpoint_every": 2, "eval_every": 2, "augment": true, "scale_jitter": 0.1
}"#;

/// `meshflow train vae --data DATA --out OUT --config CONFIG` and `extra`.
fn train_vae(data: &Path, out: &Path, config: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "train",
        "vae",
        "--data",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    meshflow(&args)
}

#[test]
fn train_reconstruct_and_eval_on_the_fixture_dataset() {
    let dir = temp_dir("train");
    let dir = dir.path();
    let run = dir.join("run");
    let _ = std::fs::remove_dir_all(&run);
    let config = dir.join("small.json");
    std::fs::write(&config, SMALL_TRAINING).unwrap();
    let data = fixture("dataset");
    let out = train_vae(&data, &run, &config, &["--val-meshes", "2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run.join("vae.manifest.json")).unwrap()).unwrap();
    assert_eq!(
        manifest["train_examples"], 32,
        "every fixture train mesh fits N = 512"
    );
    assert_eq!(manifest["latent_mean"].as_array().unwrap().len(), 8);
    assert!(manifest["sha256"].as_str().unwrap().len() == 64);
    let log = std::fs::read_to_string(run.join("metrics.jsonl")).unwrap();
    let steps = log.lines().filter(|l| l.contains("\"loss\"")).count();
    assert_eq!(steps, 4, "one metrics line per step");
    assert!(log.contains("edge_f1"), "validation lines are logged");

    let glb = dir.join("bread.glb");
    let bread = fixture("meshes/bread.obj");
    let out = meshflow(&[
        "reconstruct",
        bread.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        run.to_str().unwrap(),
        "--json",
    ]);
    let report = json(&out);
    assert_eq!(report["vertices"], 216);
    assert!(report["edge_f1"].as_f64().unwrap() >= 0.0);
    assert!(glb.is_file());

    let eval = dir.join("eval.json");
    let out = meshflow(&[
        "eval",
        "vae",
        "--weights",
        run.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
        "--split",
        "test",
        "-o",
        eval.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("skipped: 0 of 4 meshes have more than 512 vertices"),
        "the skipped meshes are reported first: {stdout}"
    );
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&eval).unwrap()).unwrap();
    assert_eq!(report["all"]["meshes"], 4);
    assert_eq!(report["token_compression"], 4.0);
    assert_eq!(
        report["buckets"].as_array().unwrap().len(),
        meshflow::eval::summary::VERTEX_BUCKETS.len()
    );

    // Weights that do not match their manifest are refused, with a reason.
    let tampered = dir.join("tampered");
    std::fs::create_dir_all(&tampered).unwrap();
    for f in ["vae.json", "vae.manifest.json"] {
        std::fs::copy(run.join(f), tampered.join(f)).unwrap();
    }
    let mut bytes = std::fs::read(run.join("vae.safetensors")).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(tampered.join("vae.safetensors"), bytes).unwrap();
    let out = meshflow(&[
        "reconstruct",
        bread.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        tampered.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sha256"));

    // A decoder-only run that adds vertex blocks starts from the whole trained decoder (the
    // blocks start as the identity): its first step's loss is that of the same run without
    // them. A decoder of another width would start afresh. `extraction_tau` is written as the
    // trained VAE's threshold and leaves the loss alone.
    let first_loss = |vertex_layers: usize| {
        let mut cfg: serde_json::Value = serde_json::from_str(SMALL_TRAINING).unwrap();
        cfg["model"]["num_layers_vertex"] = vertex_layers.into();
        cfg["decoder_only"] = true.into();
        cfg["steps"] = 1.into();
        cfg["extraction_tau"] = (-1.5).into();
        let (config, out_dir) = (
            dir.join(format!("vertex{vertex_layers}.json")),
            dir.join(format!("vertex{vertex_layers}")),
        );
        let _ = std::fs::remove_dir_all(&out_dir);
        std::fs::write(&config, cfg.to_string()).unwrap();
        let out = train_vae(
            &data,
            &out_dir,
            &config,
            &["--init", run.to_str().unwrap(), "--val-meshes", "2"],
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // The threshold chosen for extraction is the one written beside the weights.
        for file in ["vae.json", "vae.manifest.json"] {
            let written: serde_json::Value =
                serde_json::from_slice(&std::fs::read(out_dir.join(file)).unwrap()).unwrap();
            let model = written.get("model").unwrap_or(&written);
            assert_eq!(model["tau"], -1.5, "{file}");
        }
        let log = std::fs::read_to_string(out_dir.join("metrics.jsonl")).unwrap();
        let step: serde_json::Value = serde_json::from_str(log.lines().next().unwrap()).unwrap();
        step["loss"].as_f64().unwrap()
    };
    assert_eq!(first_loss(1), first_loss(0));

    // Bad requests: an unknown configuration, a point cloud to reconstruct.
    let out = train_vae(&data, &run, Path::new("nope"), &[]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A configuration with an unknown key or an impossible shape fails before any step,
    // naming the field.
    let fresh = dir.join("never");
    for (config, field) in [
        (SMALL_TRAINING.replace("\"seed\"", "\"sede\""), "sede"),
        (
            SMALL_TRAINING.replace("\"latent_dim\": 8", "\"latent_dim\": 0"),
            "latent_dim",
        ),
        (
            SMALL_TRAINING.replace("\"num_latents\": 128", "\"num_latents\": 100"),
            "num_latents",
        ),
    ] {
        let bad = dir.join("bad.json");
        std::fs::write(&bad, config).unwrap();
        let out = train_vae(&data, &fresh, &bad, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(field), "{field}: {stderr}");
        assert!(
            !fresh.join("metrics.jsonl").exists(),
            "{field}: no step ran"
        );
    }
    let points = fixture("points/stone_lantern_2048.ply");
    let out = meshflow(&[
        "reconstruct",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        run.to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_shipped_vae_reconstructs_a_fixture_mesh() {
    let weights = Path::new(env!("CARGO_MANIFEST_DIR")).join("../weights");
    let dir = temp_dir("shipped");
    let dir = dir.path();
    let glb = dir.join("lantern.glb");
    let lantern = fixture("meshes/stone_lantern.obj");
    let reconstruct = |extra: &[&str]| {
        let mut args = vec![
            "reconstruct",
            lantern.to_str().unwrap(),
            "-o",
            glb.to_str().unwrap(),
            "--weights",
            weights.to_str().unwrap(),
            "--json",
        ];
        args.extend_from_slice(extra);
        json(&meshflow(&args))
    };
    let report = reconstruct(&[]);
    assert_eq!(report["vertices"], 356);
    // Figures are whatever the shipped weights reach (BENCHMARKS.md); here: they load, pass
    // their sha256 check, run, and give a mesh with faces and finite distances.
    assert!(
        report["comparison"]["chamfer_x100"]
            .as_f64()
            .unwrap()
            .is_finite()
    );
    assert!(
        report["comparison"]["pred_topology"]["faces"]
            .as_u64()
            .unwrap()
            > 0
    );
    let back = json(&meshflow(&["inspect", glb.to_str().unwrap(), "--json"]));
    assert!(back["faces"].as_u64().unwrap() > 0);

    // The default (manifold) extraction: no edge with a third face, consistent winding.
    let topology = &report["comparison"]["pred_topology"];
    assert_eq!(topology["non_manifold_edges"], 0, "{topology}");
    assert_eq!(topology["inconsistent_winding_edges"], 0, "{topology}");
    // Algorithm 1's optional filter also leaves every edge with at most two faces; without
    // hole repair (which adds faces) it only ever removes the clique faces.
    let filtered = reconstruct(&[
        "--extraction",
        "paper",
        "--drop-non-manifold",
        "--max-hole-edges",
        "0",
    ]);
    let topology = &filtered["comparison"]["pred_topology"];
    assert_eq!(topology["non_manifold_edges"], 0, "{topology}");
    assert!(
        filtered["extract"]["faces"].as_u64().unwrap()
            <= report["extract"]["clique_faces"].as_u64().unwrap()
    );
}

#[test]
fn train_dit_on_latents_of_the_shipped_vae() {
    let weights = Path::new(env!("CARGO_MANIFEST_DIR")).join("../weights");
    let dir = temp_dir("dit");
    let dir = dir.path();
    let run = dir.join("run");
    let _ = std::fs::remove_dir_all(&run);
    let config = dir.join("dit.json");
    // The DiT's latent shape follows the shipped VAE's.
    let vae: serde_json::Value =
        serde_json::from_slice(&std::fs::read(weights.join("vae.json")).unwrap()).unwrap();
    let (num_latents, latent_dim) = (
        vae["num_latents"].as_u64().unwrap(),
        vae["latent_dim"].as_u64().unwrap(),
    );
    let tiny = |latents: u64| {
        format!(
            r#"{{"model": {{"num_latents": {latents}, "latent_dim": {latent_dim}, "width": 48, "depth": 2,
                "num_heads": 2}}, "batch_size": 4, "steps": 4, "learning_rate": 0.001,
                "warmup_steps": 1, "final_lr_ratio": 0.1, "weight_decay": 0.0, "grad_clip": 1.0,
                "ema_decay": 0.9, "seed": 1, "checkpoint_every": 2, "eval_every": 2}}"#
        )
    };
    std::fs::write(&config, tiny(num_latents)).unwrap();
    let train_steps = || -> Vec<u64> {
        std::fs::read_to_string(run.join("metrics.jsonl"))
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
            .filter(|v| v.get("lr").is_some())
            .map(|v| v["step"].as_u64().unwrap())
            .collect()
    };
    let args = |config: &Path| {
        vec![
            "train".to_string(),
            "dit".into(),
            "--data".into(),
            fixture("dataset").to_str().unwrap().into(),
            "--vae".into(),
            weights.to_str().unwrap().into(),
            "--out".into(),
            run.to_str().unwrap().into(),
            "--config".into(),
            config.to_str().unwrap().into(),
        ]
    };
    // Stopped at step 2 of the 4-step schedule (a snapshot with its weights), then the same
    // command resumes to the end: each step is trained once.
    let mut a = args(&config);
    a.extend(["--stop-at-step".to_string(), "2".into()]);
    let out = meshflow(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(run.join("dit.safetensors").is_file());
    assert_eq!(train_steps(), [1, 2]);
    let a = args(&config);
    let out = meshflow(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(train_steps(), [1, 2, 3, 4]);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run.join("dit.manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["train_examples"], 32);
    assert!(
        manifest["final_validation"]["val_loss"]
            .as_f64()
            .unwrap()
            .is_finite()
    );
    generate_with_a_trained_dit(&weights, &run, dir);
    // A DiT sized for other latents than the VAE makes is refused.
    std::fs::write(&config, tiny(num_latents / 2)).unwrap();
    let a = args(&config);
    let out = meshflow(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("latents"));
}

/// `generate` (single file, folder, bad input) and `eval generate` with the shipped VAE and
/// the DiT just trained in `run`.
fn generate_with_a_trained_dit(shipped: &Path, run: &Path, dir: &Path) {
    let weights = dir.join("weights");
    std::fs::create_dir_all(&weights).unwrap();
    for f in ["vae.safetensors", "vae.json", "vae.manifest.json"] {
        std::fs::copy(shipped.join(f), weights.join(f)).unwrap();
    }
    for f in ["dit.safetensors", "dit.json", "dit.manifest.json"] {
        std::fs::copy(run.join(f), weights.join(f)).unwrap();
    }
    let w = weights.to_str().unwrap();
    let points = fixture("points/stone_lantern_2048.ply");
    let glb = dir.join("lantern.glb");
    let out = meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
        "--steps",
        "3",
        "--vertices",
        "200",
        "--json",
    ]);
    let report = json(&out);
    assert_eq!(report["vertex_budget"], 200);
    for stage in ["condition_s", "sample_s", "decode_s", "extract_s"] {
        assert!(report["times"][stage].as_f64().unwrap() >= 0.0, "{stage}");
    }
    let back = json(&meshflow(&["inspect", glb.to_str().unwrap(), "--json"]));
    assert_eq!(back["faces"], report["topology"]["faces"]);
    assert_eq!(back["vertices"], report["topology"]["vertices"]);

    // Folder mode: every readable file gets a GLB; a bad one is reported and fails the run.
    let inputs = dir.join("inputs");
    std::fs::create_dir_all(&inputs).unwrap();
    std::fs::copy(&points, inputs.join("lantern.ply")).unwrap();
    std::fs::copy(fixture("meshes/stone_lantern.obj"), inputs.join("mesh.obj")).unwrap();
    std::fs::write(
        inputs.join("broken.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\n",
    )
    .unwrap();
    let outputs = dir.join("outputs");
    let out = meshflow(&[
        "generate",
        inputs.to_str().unwrap(),
        "-o",
        outputs.to_str().unwrap(),
        "--weights",
        w,
        "--steps",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("broken.ply") && stderr.contains("1 of 3 inputs failed"),
        "{stderr}"
    );
    assert!(outputs.join("lantern.glb").is_file() && outputs.join("mesh.glb").is_file());

    // Bad options and mismatched weights are one-line errors with status 2.
    let bad = meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
        "--vertices",
        "0",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("vertex budget 0"));

    // A second-order solver generates too; an unknown one is refused with the choices.
    for solver in ["heun", "midpoint"] {
        let report = json(&meshflow(&[
            "generate",
            points.to_str().unwrap(),
            "-o",
            glb.to_str().unwrap(),
            "--weights",
            w,
            "--steps",
            "2",
            "--solver",
            solver,
            "--json",
        ]));
        assert!(
            report["topology"]["faces"].as_u64().unwrap() > 0,
            "{solver}"
        );
    }
    let bad = meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
        "--solver",
        "rk4",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("rk4") && stderr.contains("heun"),
        "{stderr}"
    );

    // A face count steers the budget and is reported next to what came out; one the model
    // cannot make, or one beside --vertices, is refused, and no output file is left behind.
    let report = json(&meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
        "--steps",
        "2",
        "--faces",
        "150",
        "--json",
    ]));
    assert_eq!(report["faces_asked"], 150);
    assert_eq!(report["vertex_budget"], 91);
    assert!(report["fit"]["iterations"].as_u64().unwrap() > 0);
    let not_written = dir.join("never.glb");
    for (flags, message) in [
        (
            &["--faces", "5"][..],
            "5 faces is outside what the model can make: 13..=840",
        ),
        (
            &["--faces", "100", "--vertices", "50"][..],
            "cannot be used with",
        ),
    ] {
        let mut args = vec![
            "generate",
            points.to_str().unwrap(),
            "-o",
            not_written.to_str().unwrap(),
            "--weights",
            w,
        ];
        args.extend_from_slice(flags);
        let bad = meshflow(&args);
        assert_eq!(bad.status.code(), Some(2), "{flags:?}");
        let stderr = String::from_utf8_lossy(&bad.stderr);
        assert!(stderr.contains(message), "{flags:?}: {stderr}");
        assert!(!not_written.exists());
    }
    let few = dir.join("few.xyz");
    let rows: String = (0..10).map(|i| format!("{i} {} 0\n", i * i)).collect();
    std::fs::write(&few, rows).unwrap();
    let bad = meshflow(&[
        "generate",
        few.to_str().unwrap(),
        "-o",
        not_written.to_str().unwrap(),
        "--weights",
        w,
    ]);
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(stderr.contains("has 10 points; at least 16"), "{stderr}");
    assert!(!not_written.exists());
    let mut manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(weights.join("dit.manifest.json")).unwrap()).unwrap();
    let good = manifest.clone();
    // A DiT names its VAE by file and by latent space: a VAE whose decoder alone was
    // fine-tuned (another file, the same latent space) still fits it; another latent space
    // does not.
    manifest["vae_sha256"] = "0".repeat(64).into();
    std::fs::write(weights.join("dit.manifest.json"), manifest.to_string()).unwrap();
    let same_latents = meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
    ]);
    assert!(
        same_latents.status.success(),
        "{}",
        String::from_utf8_lossy(&same_latents.stderr)
    );
    manifest["vae_latent_space_sha256"] = "0".repeat(64).into();
    std::fs::write(weights.join("dit.manifest.json"), manifest.to_string()).unwrap();
    let bad = meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        w,
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("another VAE"));
    std::fs::write(weights.join("dit.manifest.json"), good.to_string()).unwrap();

    // Evaluation on a folder of meshes: ours beside the VAE bound, JSON out.
    let meshes = dir.join("eval-meshes");
    let report_path = dir.join("eval.json");
    let out = meshflow(&[
        "eval",
        "generate",
        "--input",
        fixture("meshes").to_str().unwrap(),
        "--limit",
        "2",
        "--weights",
        w,
        "--steps",
        "2",
        "--meshes",
        meshes.to_str().unwrap(),
        "-o",
        report_path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&report_path).unwrap()).unwrap();
    assert_eq!(report["all"]["meshes"], 2);
    assert_eq!(report["per_mesh"].as_array().unwrap().len(), 2);
    let text = String::from_utf8_lossy(&out.stdout);
    for line in [
        "2 meshes (",
        "  ours             CD x100 ",
        "  VAE upper bound  CD x100 ",
    ] {
        assert!(text.contains(line), "{line:?} in {text}");
    }
    assert!(text.contains("  mean per mesh: condition "), "{text}");
    assert!(
        report["all"]["vae_upper_bound"]["chamfer_x100"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(meshes.join("0.points.ply").is_file() && meshes.join("targets.json").is_file());
}

#[test]
fn the_shipped_models_generate_on_lavapipe() {
    let weights = Path::new(env!("CARGO_MANIFEST_DIR")).join("../weights");
    let dir = temp_dir("shipped-generate");
    let dir = dir.path();
    let glb = dir.join("lantern.glb");
    let points = fixture("points/stone_lantern_2048.ply");
    let report = json(&meshflow(&[
        "generate",
        points.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
        "--weights",
        weights.to_str().unwrap(),
        "--backend",
        "wgpu",
        "--steps",
        "4",
        "--json",
    ]));
    assert!(report["topology"]["faces"].as_u64().unwrap() > 0);
    let back = json(&meshflow(&["inspect", glb.to_str().unwrap(), "--json"]));
    assert_eq!(back["faces"], report["topology"]["faces"]);
    // The GLB passes the Khronos validator (node_modules from `npm ci`, as scripts/test.sh does).
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new("node")
        .arg(root.join("tests/validate-gltf.mjs"))
        .arg(&glb)
        .current_dir(&root)
        .output()
        .expect("could not run `node` (is Node.js installed?)");
    assert!(
        out.status.success(),
        "glTF validator: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Run from a folder with no weights and no `--weights`, `generate` uses the copy compiled into
/// the binary, written once into the cache folder.
#[test]
fn generate_finds_the_built_in_weights_from_any_folder() {
    let dir = temp_dir("anywhere");
    let dir = dir.path();
    let cache = dir.join("cache");
    let points = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/points/stone_lantern_2048.ply");
    let out = Command::new(env!("CARGO_BIN_EXE_meshflow"))
        .args([
            "generate",
            points.to_str().unwrap(),
            "-o",
            "out.glb",
            "--steps",
            "2",
        ])
        .current_dir(dir)
        .env_remove("MESHFLOW_WEIGHTS")
        .env("XDG_CACHE_HOME", &cache)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("out.glb").is_file());
    let written: Vec<_> = std::fs::read_dir(cache.join("meshflow"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert!(
        written.len() == 1 && written[0].starts_with("weights-"),
        "{written:?}"
    );
}
