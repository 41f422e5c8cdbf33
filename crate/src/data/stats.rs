//! Counts of a build: `stats.csv` (one row per mesh) and `stats.png` (histograms of vertex
//! and face counts over the filter's range), to see what the filter lets through.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::data::dataset::FilterOptions;
use crate::data::shards::read_manifest;

use super::error::DataError;
use super::files::{create_dir_all, write_atomic};
use super::plot;

/// Bars per histogram.
pub const HISTOGRAM_BINS: usize = 50;

/// What [`stats`] wrote and the medians it found.
#[derive(Clone, Debug)]
pub struct StatsSummary {
    pub meshes: usize,
    pub median_vertices: usize,
    pub median_faces: usize,
    pub csv: PathBuf,
    pub png: PathBuf,
    /// The histograms' ranges: the default filter's vertex and face limits.
    pub max_vertices: usize,
    pub max_faces: usize,
    pub bins: usize,
}

/// The two lines `meshflow data stats` prints: the medians and what was written.
impl fmt::Display for StatsSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (n, v, faces) = (self.meshes, self.median_vertices, self.median_faces);
        writeln!(f, "{n} meshes; median {v} vertices, {faces} faces")?;
        let (csv, png) = (self.csv.display(), self.png.display());
        let (v, faces, bins) = (self.max_vertices, self.max_faces, self.bins);
        write!(
            f,
            "wrote {csv} and {png} (top: vertices 0..{v}, bottom: faces 0..{faces}, "
        )?;
        write!(f, "{bins} bins each)")
    }
}

/// One histogram panel: `values` binned over `0..=max`.
struct HistPanel {
    title: String,
    values: Vec<usize>,
    max: usize,
    color: [u8; 3],
}

/// Histogram panels stacked vertically, each with a title, labelled axes and
/// light grid lines, as PNG bytes. Deterministic: same panels, same bytes.
fn histogram_png(panels: &[HistPanel]) -> Result<Vec<u8>, png::EncodingError> {
    // 76 px of count labels, 700 px of bars, room for the last value label.
    const W: usize = 820;
    const PANEL_H: usize = 320;
    const BINS: usize = HISTOGRAM_BINS;
    const BAR_W: usize = 14;
    const SCALE: usize = 2;
    let mut img = plot::Canvas::new(W, PANEL_H * panels.len(), [255, 255, 255]);
    for (p, panel) in panels.iter().enumerate() {
        let top_y = p * PANEL_H;
        let mut bins = [0usize; BINS];
        for &v in &panel.values {
            bins[(v * BINS / (panel.max + 1)).min(BINS - 1)] += 1;
        }
        let tallest = bins.iter().copied().max().unwrap_or(0).max(1);
        // Left margin for the count labels, room above for the title and
        // below for the value labels.
        let frame = plot::Frame {
            x0: 76,
            y_base: top_y + PANEL_H - 44,
            w: BINS * BAR_W,
            h: PANEL_H - 44 - 64,
        };
        img.text(frame.x0, top_y + 14, &panel.title, SCALE, plot::BLACK);
        img.text(
            frame.x0 + 6,
            frame.y_base - frame.h - 22,
            "meshes",
            SCALE,
            [90, 90, 90],
        );
        for (b, &count) in bins.iter().enumerate() {
            let bar_h = count * frame.h / tallest;
            img.fill_rect(
                frame.x0 + b * BAR_W,
                frame.y_base - bar_h,
                BAR_W - 1,
                bar_h,
                panel.color,
            );
        }
        img.axes(
            frame,
            panel.max + 1,
            plot::nice_step(panel.max, 4),
            tallest,
            plot::nice_step(tallest, 4),
            SCALE,
        );
    }
    img.to_png()
}

/// Writes `stats.csv` and `stats.png` for the build in `dir` into `out` (default: `dir`).
pub fn stats(dir: &Path, out: Option<&Path>) -> Result<StatsSummary, DataError> {
    let entries = read_manifest(dir)?;
    let out = out.map_or_else(|| dir.to_path_buf(), Path::to_path_buf);
    create_dir_all(&out)?;
    let mut csv =
        String::from("id,split,package,path,vertices,faces,max_degree,boundary_edges,components\n");
    for e in &entries {
        csv.push_str(&format!(
            "{},{},{},\"{}\",{},{},{},{},{}\n",
            e.id,
            e.split,
            e.package,
            e.path.replace('"', "\"\""),
            e.vertices,
            e.faces,
            e.max_degree,
            e.topology.boundary_edges,
            e.topology.components
        ));
    }
    let csv_path = out.join("stats.csv");
    write_atomic(&csv_path, csv.as_bytes())?;
    let f = FilterOptions::default();
    let png_path = out.join("stats.png");
    let median = |mut v: Vec<usize>| {
        v.sort_unstable();
        v.get(v.len() / 2).copied().unwrap_or(0)
    };
    let vertices: Vec<usize> = entries.iter().map(|e| e.vertices).collect();
    let faces: Vec<usize> = entries.iter().map(|e| e.faces).collect();
    let (median_v, median_f) = (median(vertices.clone()), median(faces.clone()));
    let png = histogram_png(&[
        HistPanel {
            title: format!(
                "Vertices per mesh ({} meshes, median {})",
                plot::thousands(entries.len()),
                plot::thousands(median_v)
            ),
            values: vertices,
            max: f.max_vertices,
            color: [40, 90, 200],
        },
        HistPanel {
            title: format!("Faces per mesh (median {})", plot::thousands(median_f)),
            values: faces,
            max: f.max_faces,
            color: [200, 90, 40],
        },
    ])
    .map_err(|error| DataError::Png {
        path: png_path.clone(),
        error,
    })?;
    write_atomic(&png_path, &png)?;
    Ok(StatsSummary {
        meshes: entries.len(),
        median_vertices: median_v,
        median_faces: median_f,
        csv: csv_path,
        png: png_path,
        max_vertices: f.max_vertices,
        max_faces: f.max_faces,
        bins: HISTOGRAM_BINS,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;
    use std::io::Cursor;

    use crate::data::build::{BuildOptions, build};
    use crate::data::export::export_mesh;
    use crate::data::test_support::{fake_package, temp_dir};
    use crate::io::Limits;

    #[test]
    fn the_summary_reads_as_two_lines() {
        let s = StatsSummary {
            meshes: 7,
            median_vertices: 40,
            median_faces: 60,
            csv: "d/stats.csv".into(),
            png: "d/stats.png".into(),
            max_vertices: 4096,
            max_faces: 8000,
            bins: 50,
        };
        assert_eq!(
            s.to_string(),
            "7 meshes; median 40 vertices, 60 faces\nwrote d/stats.csv and d/stats.png (top: \
             vertices 0..4096, bottom: faces 0..8000, 50 bins each)"
        );
    }

    #[test]
    fn histogram_png_has_fixed_size_and_is_deterministic() {
        let panels = || {
            vec![
                HistPanel {
                    title: "Vertices per mesh (7 meshes, median 40)".into(),
                    values: vec![3, 40, 40, 41, 900, 4096, 5000],
                    max: 4096,
                    color: [40, 90, 200],
                },
                HistPanel {
                    title: "Faces per mesh (median 60)".into(),
                    values: vec![1, 60, 60, 61, 7999, 8000, 0],
                    max: 8000,
                    color: [200, 90, 40],
                },
            ]
        };
        let a = histogram_png(&panels()).unwrap();
        let b = histogram_png(&panels()).unwrap();
        assert_eq!(a, b, "two renders of the same data differ");
        let info = png::Decoder::new(Cursor::new(&a))
            .read_info()
            .unwrap()
            .info()
            .clone();
        assert_eq!((info.width, info.height), (820, 640));
        assert_eq!(info.color_type, png::ColorType::Rgb);
    }

    #[test]
    fn stats_and_show_read_the_build() {
        let root = temp_dir("stats");
        let pkg = fake_package(&root);
        let out = root.join("out");
        build(&[pkg], &out, None, &BuildOptions::default(), &mut |_| {}).unwrap();
        stats(&out, None).unwrap();
        let csv = fs::read_to_string(out.join("stats.csv")).unwrap();
        let entries = read_manifest(&out).unwrap();
        assert_eq!(csv.lines().count(), entries.len() + 1);
        assert!(
            fs::read(out.join("stats.png"))
                .unwrap()
                .starts_with(b"\x89PNG")
        );
        let e = &entries[0];
        let glb = root.join("one.obj");
        export_mesh(&out, &e.id, &glb, true).unwrap();
        let m = crate::io::read_path(&glb, &Limits::default()).unwrap();
        assert_eq!(m.faces.len(), e.faces);
        assert!(export_mesh(&out, "nope", &glb, false).is_err());
        let _ = fs::remove_dir_all(&root);
    }
}
