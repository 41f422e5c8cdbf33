//! `meshflow verify --golden DIR`: runs the golden `vae_small` and `dit_small` through this
//! build on the chosen backend and prints the largest difference per tensor, so a new machine
//! or GPU driver can be checked against the reference numerics (tolerance 1e-4).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use glam::Vec3;
use meshflow::burn::tensor::{Device, Tensor, TensorData};
use meshflow::device::{BackendKind, device};
use meshflow::model::dit::{Dit, DitConfig, Rope, is_image_path};
use meshflow::model::sampler::sample;
use meshflow::model::schedule::ScheduleMode;
use meshflow::model::tokens::assemble_features;
use meshflow::model::{MeshVae, TensorMap, Trace, VaeConfig, load_module, spacetime_distances};

/// Largest accepted absolute difference.
pub const TOLERANCE: f32 = 1e-4;

#[derive(Args)]
pub struct VerifyArgs {
    /// Folder with vae_small.safetensors and dit_small.safetensors.
    #[arg(long)]
    golden: PathBuf,
    #[arg(long, default_value = "cpu", value_parser = crate::train::backend_parser())]
    backend: BackendKind,
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec::<f32>()
        .expect("f32 data")
}

struct Golden {
    map: TensorMap,
    rows: Vec<(String, f32)>,
}

impl Golden {
    fn load(dir: &Path, name: &str) -> Result<Self> {
        let path = dir.join(format!("{name}.safetensors"));
        let bytes =
            std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        // Float tensors only: the edge lists are integers and not compared here.
        Ok(Self {
            map: TensorMap::floats_of_safetensors(&bytes)?,
            rows: Vec::new(),
        })
    }

    fn get(&self, name: &str) -> Result<&(Vec<usize>, Vec<f32>)> {
        self.map
            .tensors
            .get(name)
            .with_context(|| format!("golden tensor {name} missing"))
    }

    fn tensor<const D: usize>(&self, name: &str, device: &Device) -> Result<Tensor<D>> {
        self.map
            .tensor::<D>(name, device)
            .with_context(|| format!("golden tensor {name} missing or of another rank"))
    }

    fn compare(&mut self, label: &str, got: &[f32], key: &str) -> Result<()> {
        let want = &self.get(key)?.1;
        if want.len() != got.len() {
            bail!(
                "{label}: {} values, the reference has {}",
                got.len(),
                want.len()
            );
        }
        let err = got
            .iter()
            .zip(want)
            .map(|(a, b)| (a - b).abs())
            .fold(0f32, f32::max);
        self.rows.push((label.to_string(), err));
        Ok(())
    }
}

fn verify_vae(dir: &Path, device: &Device) -> Result<Vec<(String, f32)>> {
    let mut g = Golden::load(dir, "vae_small")?;
    let params =
        TensorMap::from_safetensors(&std::fs::read(dir.join("vae_small.safetensors"))?, "param.")?;
    let cfg = VaeConfig::vae_small();
    let vae = load_module(MeshVae::new(&cfg, device), &params, &|_| false)?;
    let verts = g.get("input.padded_verts")?.1.clone();
    let normals = g.get("input.verts_normal")?.1.clone();
    let neighbours = g.get("input.neighbor_points")?.1.clone();
    let tokens = cfg.tokens();
    let per = 3 * cfg.max_degree;
    let mut x = Vec::new();
    for i in 0..verts.len() / 3 {
        let nb: Vec<Vec3> = neighbours[i * per..(i + 1) * per]
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        let v = Vec3::from_slice(&verts[i * 3..i * 3 + 3]);
        let n = Vec3::from_slice(&normals[i * 3..i * 3 + 3]);
        assemble_features(v, n, &nb, &tokens, &mut x);
    }
    g.compare("x", &x, "output.x")?;
    let b = verts.len() / 3 / cfg.num_vertices;
    let xt = Tensor::<3>::from_data(
        TensorData::new(x, [b, cfg.num_vertices, cfg.in_channels()]),
        device,
    );
    let mut trace = Trace::recording();
    let posterior = vae.encode(xt, &mut trace);
    g.compare(
        "posterior_mean",
        &values(posterior.mean.clone()),
        "output.posterior_mean",
    )?;
    g.compare(
        "posterior_logvar",
        &values(posterior.logvar),
        "output.posterior_logvar",
    )?;
    let out = vae.decode(posterior.mean, &mut trace);
    for (name, t) in std::mem::take(&mut trace.tensors) {
        g.compare(&name, &values(t), &format!("inter.{name}"))?;
    }
    g.compare("mask", &values(out.mask_logits), "output.mask")?;
    g.compare("verts", &values(out.positions), "output.verts")?;
    g.compare("verts_normal", &values(out.normals), "output.verts_normal")?;
    g.compare(
        "adjacency_emb",
        &values(out.edge_embeddings.clone()),
        "output.adjacency_emb",
    )?;
    let st = spacetime_distances(out.edge_embeddings.narrow(0, 0, 1));
    g.compare("spacetime", &values(st), "output.spacetime")?;
    let synthetic: Tensor<2> = g.tensor("input.synthetic_adjacency_emb", device)?;
    let st = spacetime_distances(synthetic.unsqueeze::<3>());
    g.compare(
        "synthetic_spacetime",
        &values(st),
        "output.synthetic_spacetime",
    )?;
    Ok(g.rows)
}

fn verify_dit(dir: &Path, device: &Device) -> Result<Vec<(String, f32)>> {
    let mut g = Golden::load(dir, "dit_small")?;
    let params =
        TensorMap::from_safetensors(&std::fs::read(dir.join("dit_small.safetensors"))?, "param.")?;
    let cfg = DitConfig::dit_small();
    let dit = load_module(Dit::new(&cfg, device), &params, &is_image_path)?;
    let t = g.get("input.timestep")?.1.clone();
    let positions: Vec<[f32; 3]> = g
        .get("input.rope_input")?
        .1
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let batch = t.len();
    let rope = Rope::new(&positions, batch, cfg.width / cfg.num_heads, device);
    let cond: Tensor<2> = g.tensor("input.proj_cond_on_temb", device)?;
    g.compare(
        "temb",
        &values(dit.time_embedding(&t, cond.clone())),
        "inter.temb",
    )?;
    let x: Tensor<3> = g.tensor("input.x", device)?;
    let mut trace = Trace::recording();
    let out = dit.forward(x, &t, cond.clone(), &rope, &mut trace);
    for (name, tensor) in std::mem::take(&mut trace.tensors) {
        g.compare(&name, &values(tensor), &format!("inter.{name}"))?;
    }
    g.compare("sample", &values(out), "output.sample")?;
    let noise: Tensor<3> = g.tensor("input.noise", device)?;
    let mut steps = Vec::new();
    let sampled = sample(
        &dit,
        noise,
        cond,
        &rope,
        10,
        ScheduleMode::Reference,
        &mut |_, _, x| {
            steps.extend(values(x.clone()));
            true
        },
    )?;
    g.compare("sample_trace", &steps, "output.sample_trace")?;
    g.compare("sampled", &values(sampled), "output.sampled")?;
    Ok(g.rows)
}

pub fn run(args: VerifyArgs) -> Result<()> {
    let kind = args.backend;
    let device = device(kind).map_err(|e| anyhow::anyhow!(e))?;
    let mut failed = 0;
    for (model, rows) in [
        ("vae_small", verify_vae(&args.golden, &device)?),
        ("dit_small", verify_dit(&args.golden, &device)?),
    ] {
        for (name, err) in rows {
            let ok = err < TOLERANCE;
            failed += !ok as usize;
            println!(
                "{model:10} {name:28} max abs diff {err:.2e} {}",
                if ok { "ok" } else { "FAIL" }
            );
        }
    }
    if failed > 0 {
        bail!(
            "{failed} tensor(s) differ from the reference by {TOLERANCE} or more on {}",
            kind.name()
        );
    }
    println!(
        "all tensors within {TOLERANCE:e} of the reference on {}",
        kind.name()
    );
    Ok(())
}
