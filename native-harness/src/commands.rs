//! The geometry commands: inspect, sample, convert, compare, extract.

use std::path::Path;

use anyhow::{Context, Result};
use meshflow::Mesh;
use meshflow::eval::metrics::{CompareOptions, compare_meshes};
use meshflow::extract::round_trip::{RoundTripError, round_trip};
use meshflow::geometry::clean::{CleanOptions, clean};
use meshflow::geometry::inspect::Inspection;
use meshflow::geometry::sample::sample_surface;
use meshflow::geometry::topology::TopologyReport;
use meshflow::io::{Limits, read_path, write_path};
use serde::Serialize;

use crate::BadInput;
use crate::extract_args::ExtractArgs;
use crate::progress::step;

fn read(path: &Path) -> Result<Mesh> {
    step(&format!("reading {}", path.display()), || {
        read_path(path, &Limits::default())
    })
    .with_context(|| format!("cannot read {}", path.display()))
}

fn write(mesh: &Mesh, path: &Path) -> Result<()> {
    write_path(mesh, path).with_context(|| format!("cannot write {}", path.display()))
}

fn print_json(value: &impl Serialize) -> Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// Prints a topology report as aligned `name: value` lines.
fn print_topology(title: &str, t: &TopologyReport) {
    println!("{title}");
    let value = serde_json::to_value(t).expect("report serialises");
    for (k, v) in value.as_object().expect("struct") {
        println!("  {:<28}{v}", k.replace('_', " "));
    }
}

/// A report as printed: the file it is about, then the report's own fields.
#[derive(Serialize)]
struct OfFile<'a, T> {
    file: String,
    #[serde(flatten)]
    report: &'a T,
}

/// `meshflow inspect`: the summary of a mesh or point cloud, as text or JSON.
pub fn inspect(file: &Path, json: bool) -> Result<()> {
    let mesh = read(file)?;
    let report = Inspection::of(&mesh);
    let file = file.display().to_string();
    if json {
        return print_json(&OfFile {
            file,
            report: &report,
        });
    }
    println!("{file}");
    let kind = if report.point_cloud {
        "point cloud"
    } else {
        "triangle mesh"
    };
    println!(
        "  {kind}: {} vertices, {} faces, normals: {}",
        report.vertices, report.faces, report.has_normals
    );
    println!(
        "  bounding box: {:?} .. {:?}",
        report.bbox_min, report.bbox_max
    );
    println!(
        "  surface area: {:.6}   max vertex degree: {}",
        report.surface_area, report.max_vertex_degree
    );
    print_topology("topology", &report.topology);
    Ok(())
}

pub fn sample(
    mesh_path: &Path,
    count: usize,
    output: &Path,
    seed: u64,
    with_normals: bool,
) -> Result<()> {
    if count == 0 {
        return Err(BadInput("the number of points (-n) must be at least 1".into()).into());
    }
    let mesh = read(mesh_path)?;
    let samples = step("sampling", || sample_surface(&mesh, count, seed))
        .with_context(|| format!("cannot sample {}", mesh_path.display()))?;
    let mut cloud = Mesh::from_points(samples.points);
    if with_normals {
        cloud.normals = samples.normals;
    }
    write(&cloud, output)?;
    println!(
        "wrote {} points to {}",
        cloud.positions.len(),
        output.display()
    );
    Ok(())
}

pub fn convert(input: &Path, output: &Path, do_clean: bool) -> Result<()> {
    let mut mesh = read(input)?;
    if do_clean {
        let (cleaned, report) = clean(&mesh, &CleanOptions::default());
        println!("cleaned: {}", serde_json::to_string(&report)?);
        mesh = cleaned;
    }
    write(&mesh, output)?;
    println!(
        "wrote {} ({} vertices, {} faces)",
        output.display(),
        mesh.positions.len(),
        mesh.faces.len()
    );
    Ok(())
}

pub fn compare(pred: &Path, gt: &Path, samples: usize, seed: u64, json: bool) -> Result<()> {
    let (p, g) = (read(pred)?, read(gt)?);
    let cmp = step("comparing", || {
        compare_meshes(
            &p,
            &g,
            &CompareOptions {
                samples,
                seed,
                ..Default::default()
            },
        )
    })
    .context("cannot compare")?;
    if json {
        return print_json(&cmp);
    }
    println!("{} vs {}", pred.display(), gt.display());
    let value = serde_json::to_value(&cmp)?;
    for (k, v) in value.as_object().expect("struct") {
        if !v.is_object() {
            println!("  {:<28}{v}", k.replace('_', " "));
        }
    }
    let sharp = &cmp.sharp;
    let ecd = sharp
        .edge_chamfer_x100
        .map_or("none (neither has sharp edges)".to_string(), |d| {
            format!("{d:.3}")
        });
    println!(
        "  sharp edges (> 30 deg)      {} predicted, {} ground truth",
        sharp.pred_sharp_edges, sharp.gt_sharp_edges
    );
    println!("  edge chamfer x100           {ecd}");
    println!(
        "  edge f-score @0.01          {:.4} (precision {:.4}, recall {:.4})",
        sharp.edge_f_score.f_score, sharp.edge_f_score.precision, sharp.edge_f_score.recall
    );
    println!(
        "  faces                       {} predicted, {} ground truth ({:.2}x)",
        cmp.pred_topology.faces,
        cmp.gt_topology.faces,
        cmp.pred_topology.faces as f64 / cmp.gt_topology.faces.max(1) as f64
    );
    print_topology("prediction topology", &cmp.pred_topology);
    print_topology("ground-truth topology", &cmp.gt_topology);
    Ok(())
}

/// `meshflow extract`: the round trip of a mesh through its own edges, as text or JSON;
/// optionally writes the extracted mesh.
pub fn extract(
    mesh_path: &Path,
    output: Option<&Path>,
    extract: &ExtractArgs,
    json: bool,
) -> Result<()> {
    let mesh = read(mesh_path)?;
    let file = mesh_path.display().to_string();
    let (result, report) = match round_trip(&mesh, &extract.options()) {
        Ok(done) => done,
        // Input the command cannot work with exits with status 2; the messages name the file.
        Err(RoundTripError::PointCloud) => {
            let msg = format!("{file} is a point cloud: extract needs a mesh with faces");
            return Err(BadInput(msg).into());
        }
        Err(RoundTripError::Empty) => {
            return Err(BadInput(format!("{file} is empty after cleaning")).into());
        }
        Err(RoundTripError::Extract(e)) => return Err(e.into()),
    };
    if let Some(path) = output {
        write(&result, path)?;
    }
    if json {
        return print_json(&OfFile {
            file,
            report: &report,
        });
    }
    println!("{file}");
    println!("  cleaned: {}", serde_json::to_string(&report.clean)?);
    println!(
        "  faces: {} -> {} extracted ({} lost, {} extra, {} flipped)",
        report.faces,
        report.extracted_faces,
        report.lost_faces,
        report.extra_faces,
        report.flipped_faces
    );
    println!("  extraction: {}", serde_json::to_string(&report.extract)?);
    print_topology("topology before", &report.topology_before);
    print_topology("topology after", &report.topology_after);
    if let Some(path) = output {
        println!("wrote {}", path.display());
    }
    Ok(())
}
