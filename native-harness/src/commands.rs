//! The geometry commands: inspect, sample, convert, compare, extract.

use std::path::Path;

use anyhow::{Context, Result};
use meshflow::eval::metrics::{CompareOptions, compare_meshes};
use meshflow::extract::{ExtractOptions, ExtractReport, FaceSupport, extract_mesh};
use meshflow::geometry::clean::{CleanOptions, CleanReport, clean};
use meshflow::geometry::normalize::Normalization;
use meshflow::geometry::normals::vertex_normals;
use meshflow::geometry::sample::sample_surface;
use meshflow::geometry::topology::{
    TopologyReport, adjacency, edges, rotate_min_first, sorted_face,
};
use meshflow::io::{Limits, read_path, write_path};
use meshflow::model::tokens::{token_edges, vertex_order};
use meshflow::{Aabb, Mesh};
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

#[derive(Serialize)]
struct Inspection {
    file: String,
    vertices: usize,
    faces: usize,
    point_cloud: bool,
    has_normals: bool,
    bbox_min: [f32; 3],
    bbox_max: [f32; 3],
    surface_area: f64,
    max_vertex_degree: usize,
    topology: TopologyReport,
}

pub fn inspect(file: &Path, json: bool) -> Result<()> {
    let mesh = read(file)?;
    let aabb = mesh.aabb().unwrap_or(Aabb {
        min: glam::Vec3::ZERO,
        max: glam::Vec3::ZERO,
    });
    let degree = adjacency(mesh.positions.len(), &edges(&mesh.faces))
        .iter()
        .map(Vec::len)
        .max();
    let report = Inspection {
        file: file.display().to_string(),
        vertices: mesh.positions.len(),
        faces: mesh.faces.len(),
        point_cloud: mesh.is_point_cloud(),
        has_normals: !mesh.normals.is_empty(),
        bbox_min: aabb.min.to_array(),
        bbox_max: aabb.max.to_array(),
        surface_area: mesh.area(),
        max_vertex_degree: degree.unwrap_or(0),
        topology: TopologyReport::of(&mesh),
    };
    if json {
        return print_json(&report);
    }
    println!("{}", report.file);
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
    print_topology("prediction topology", &cmp.pred_topology);
    print_topology("ground-truth topology", &cmp.gt_topology);
    Ok(())
}

#[derive(Serialize)]
struct RoundTrip {
    file: String,
    clean: CleanReport,
    /// Faces of the cleaned mesh, the reference for the counts below.
    faces: usize,
    extracted_faces: usize,
    /// Faces of the cleaned mesh that extraction did not produce.
    lost_faces: usize,
    /// Extracted faces that the cleaned mesh does not have (non-face 3-cliques, filled holes).
    extra_faces: usize,
    /// Faces produced with the opposite winding (the normal rule disagrees with the source).
    flipped_faces: usize,
    extract: ExtractReport,
    topology_before: TopologyReport,
    topology_after: TopologyReport,
}

pub fn extract(
    mesh_path: &Path,
    output: Option<&Path>,
    extract: &ExtractArgs,
    json: bool,
) -> Result<()> {
    let mesh = read(mesh_path)?;
    if mesh.is_point_cloud() {
        let msg = format!(
            "{} is a point cloud: extract needs a mesh with faces",
            mesh_path.display()
        );
        return Err(BadInput(msg).into());
    }
    let (cleaned, clean_report) = clean(&mesh, &CleanOptions::default());
    let aabb = cleaned
        .aabb()
        .ok_or_else(|| BadInput(format!("{} is empty after cleaning", mesh_path.display())))?;
    let model_frame = Normalization::to_model_frame(aabb).apply_mesh(&cleaned);
    // The token layer without its features (which would cost ~1.4 KB per vertex): every vertex
    // is a token in the VAE's order, and the ground-truth adjacency is renumbered into it.
    let order = vertex_order(&model_frame.positions);
    let normals = vertex_normals(&model_frame.positions, &model_frame.faces);
    let token_positions: Vec<_> = order
        .iter()
        .map(|&v| model_frame.positions[v as usize])
        .collect();
    let token_normals: Vec<_> = order.iter().map(|&v| normals[v as usize]).collect();
    let edges = token_edges(&model_frame.faces, &order);
    // Keep every token (no compaction) so the report can compare with the source's faces.
    let opts = ExtractOptions {
        compact: false,
        ..extract.options()
    };
    let (out, extract_report) = extract_mesh(
        &token_positions,
        &token_normals,
        &edges,
        FaceSupport::Geometric,
        &opts,
    )?;
    // Back to the cleaned mesh's numbering and coordinates.
    let original = |t: u32| order[t as usize];
    let faces: Vec<[u32; 3]> = out.faces.iter().map(|f| f.map(original)).collect();
    let result = Mesh {
        positions: cleaned.positions.clone(),
        normals: Vec::new(),
        faces,
    };

    let as_set = |faces: &[[u32; 3]]| {
        let mut v: Vec<[u32; 3]> = faces.iter().map(|&f| sorted_face(f)).collect();
        v.sort_unstable();
        v
    };
    let (before, after) = (as_set(&cleaned.faces), as_set(&result.faces));
    let lost = before
        .iter()
        .filter(|f| after.binary_search(f).is_err())
        .count();
    let extra = after
        .iter()
        .filter(|f| before.binary_search(f).is_err())
        .count();
    let mut oriented: Vec<[u32; 3]> = cleaned.faces.iter().map(|&f| rotate_min_first(f)).collect();
    oriented.sort_unstable();
    let flipped = result
        .faces
        .iter()
        .map(|&f| rotate_min_first(f))
        .filter(|f| {
            oriented.binary_search(f).is_err()
                && oriented.binary_search(&[f[0], f[2], f[1]]).is_ok()
        })
        .count();
    let report = RoundTrip {
        file: mesh_path.display().to_string(),
        clean: clean_report,
        faces: cleaned.faces.len(),
        extracted_faces: result.faces.len(),
        lost_faces: lost,
        extra_faces: extra,
        flipped_faces: flipped,
        extract: extract_report,
        topology_before: TopologyReport::of(&cleaned),
        topology_after: TopologyReport::of(&result),
    };
    if let Some(path) = output {
        write(&result, path)?;
    }
    if json {
        return print_json(&report);
    }
    println!("{}", report.file);
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
