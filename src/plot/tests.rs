//! Tests of the plot module: decoded outputs, pixel positions, errors.

use std::fs::File;
use std::io::BufReader;
use std::path::PathBuf;

use plotters::style::{Color, RGBColor};

use super::*;

/// A fresh (emptied) folder under the system temp dir for one test; the outputs stay there
/// for inspection.
fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("cellsurf-plot-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Decodes a PNG file into (width, height, RGB8 pixels).
fn decode_png(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(BufReader::new(File::open(path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

fn px(rgb: &[u8], w: u32, i: u32, j: u32) -> [u8; 3] {
    let k = ((j * w + i) * 3) as usize;
    [rgb[k], rgb[k + 1], rgb[k + 2]]
}

fn rgb(c: RGBColor) -> [u8; 3] {
    [c.0, c.1, c.2]
}

/// A palette with one clearly distinct colour per state 0..6.
fn test_palette() -> Palette {
    Palette {
        colors: vec![
            RGBColor(10, 10, 10),
            RGBColor(200, 0, 0),
            RGBColor(0, 200, 0),
            RGBColor(0, 0, 200),
            RGBColor(200, 200, 0),
            RGBColor(0, 200, 200),
        ],
    }
}

fn sample_field(nx: usize, ny: usize, hex: bool) -> CellField {
    let mut f = CellField::new(nx, ny, hex);
    for y in 0..ny {
        for x in 0..nx {
            let front = ny as f64 * (0.3 + 0.1 * (x as f64 * 0.15).sin());
            let yf = y as f64;
            f.states[y * nx + x] = if yf < front {
                2
            } else if yf < front + 1.0 {
                1
            } else {
                0
            };
        }
    }
    f
}

#[test]
fn square_rasterize_puts_each_cell_at_its_centre() {
    // 3 x 2 field, states 0..6 so each cell has its own colour.
    let field = CellField {
        nx: 3,
        ny: 2,
        hex: false,
        states: vec![0, 1, 2, 3, 4, 5],
    };
    let pal = test_palette();
    // 30 x 20 pixels: exactly 10 pixels per cell, no letterboxing.
    let img = rasterize(&field, &pal, 30, 20);
    assert_eq!(img.len(), 30 * 20 * 3);
    for y in 0..2u32 {
        for x in 0..3u32 {
            let state = field.states[(y * 3 + x) as usize];
            // Row 0 at the bottom: lattice row y spans picture rows (1 - y) * 10 ..
            let (i, j) = (x * 10 + 5, (1 - y) * 10 + 5);
            assert_eq!(px(&img, 30, i, j), rgb(pal.color(state)), "cell ({x}, {y})");
        }
    }
    // Letterboxing keeps the aspect ratio: a 60 x 60 buffer has background above and below.
    let img = rasterize(&field, &pal, 60, 60);
    assert_eq!(px(&img, 60, 30, 2), rgb(BACKGROUND));
    assert_eq!(px(&img, 60, 30, 57), rgb(BACKGROUND));
    assert_eq!(px(&img, 60, 5, 25), rgb(pal.color(3)));
}

#[test]
fn hex_rasterize_offsets_odd_rows() {
    // 4 x 2 hex field: row 0 states 0, 1, 2, 3; row 1 states 4, 5, 4, 5.
    let field = CellField {
        nx: 4,
        ny: 2,
        hex: true,
        states: vec![0, 1, 2, 3, 4, 5, 4, 5],
    };
    let pal = test_palette();
    let (pw, ph) = field.physical_size();
    assert!((pw - 4.5).abs() < 1e-12);
    assert!((ph - (3f64.sqrt() / 2.0 + 2.0 / 3f64.sqrt())).abs() < 1e-12);
    let scale = 40.0; // pixels per cell width
    let (w, h) = ((pw * scale).round() as u32, (ph * scale).round() as u32);
    let img = rasterize(&field, &pal, w, h);
    // Physical -> pixel with the extent xmin = -0.5, ymax = (ny-1)*sqrt(3)/2 + 1/sqrt(3).
    let ymax = 3f64.sqrt() / 2.0 + 1.0 / 3f64.sqrt();
    let to_px = |x: f64, y: f64| (((x + 0.5) * scale) as u32, ((ymax - y) * scale) as u32);

    // Centre of odd-row cell (1, 1) at (1.5, sqrt(3)/2): its own colour (state 5).
    let (i, j) = to_px(1.5, 3f64.sqrt() / 2.0);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(5)));
    // Where an unshifted row would put cell (1, 1), x = 1.0, the boundary between cells (0, 1)
    // and (1, 1) lies; just left of it is cell (0, 1) (state 4), right of it cell (1, 1).
    let (i, j) = to_px(0.9, 3f64.sqrt() / 2.0);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(4)));
    let (i, j) = to_px(1.1, 3f64.sqrt() / 2.0);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(5)));
    // Even row is not shifted: centre of cell (1, 0) at (1, 0) shows state 1.
    let (i, j) = to_px(1.0, 0.0);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(1)));
    // Odd row reaches half a cell further right: (3.8, row 1) is in cell (3, 1) (state 5),
    // while (3.8, row 0) is beyond the even row's last cell, which ends at 3.5 (background).
    let (i, j) = to_px(3.8, 3f64.sqrt() / 2.0);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(5)));
    let (i, j) = to_px(3.8, 0.0);
    assert_eq!(px(&img, w, i, j), rgb(BACKGROUND));
    // Pointy tops: straight above the centre of cell (0, 0) up to 1/sqrt(3) is still cell
    // (0, 0), but the upper corner region beside the point belongs to the next row.
    let (i, j) = to_px(0.0, 0.55);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(0)));
    let (i, j) = to_px(0.45, 0.5);
    assert_eq!(px(&img, w, i, j), rgb(pal.color(4)));
}

#[test]
fn small_cells_keep_thin_interfaces_visible() {
    // 100 x 100 square field: occupied rows 0..53, one interface row 53, empty above; drawn at
    // 10 x 10 pixels, 10 x 10 cells per pixel.
    let mut field = CellField::new(100, 100, false);
    for y in 0..54 {
        for x in 0..100 {
            field.states[y * 100 + x] = if y == 53 { 1 } else { 2 };
        }
    }
    let pal = test_palette();
    let img = rasterize(&field, &pal, 10, 10);
    // Picture row 4 holds lattice rows 50..60 (occupied, interface, empty): the interface wins.
    for i in 0..10 {
        assert_eq!(px(&img, 10, i, 3), rgb(pal.color(0)));
        assert_eq!(px(&img, 10, i, 4), rgb(pal.color(1)));
        assert_eq!(px(&img, 10, i, 5), rgb(pal.color(2)));
    }
    // The same on a hexagonal lattice: every column of the picture shows the interface.
    field.hex = true;
    let img = rasterize(&field, &pal, 100, 100);
    for i in 5..95 {
        let interface = (0..100).any(|j| px(&img, 100, i, j) == rgb(pal.color(1)));
        assert!(interface, "column {i}");
    }
}

#[test]
fn rasterize_never_panics_on_bad_fields() {
    let pal = Palette { colors: vec![] };
    let short = CellField {
        nx: 5,
        ny: 5,
        hex: true,
        states: vec![1; 3],
    };
    assert_eq!(rasterize(&short, &pal, 20, 20).len(), 20 * 20 * 3);
    assert!(rasterize(&short, &pal, 0, 20).is_empty());
    let empty = CellField::new(0, 3, false);
    let img = rasterize(&empty, &Palette::default(), 4, 4);
    assert!(img.chunks(3).all(|p| p == rgb(BACKGROUND)));
}

#[test]
fn extreme_sizes_do_not_panic() {
    let dir = out_dir("extreme");
    let pal = Palette::default();
    // A huge declared field with few states: rasterize treats missing states as empty.
    let huge = CellField {
        nx: 1 << 40,
        ny: 1 << 40,
        hex: true,
        states: vec![2; 10],
    };
    assert_eq!(rasterize(&huge, &pal, 8, 8).len(), 8 * 8 * 3);
    // ... but the drawing functions refuse it.
    let panel = Panel {
        title: "huge".into(),
        field: huge,
    };
    assert!(lattice_panels(&dir.join("huge.png"), "", &[panel], 1, &pal, 50).is_err());
    // Tiny panels with long titles, and the smallest charts.
    let panel = Panel {
        title: "a very long panel title that cannot fit".repeat(3),
        field: sample_field(5, 5, true),
    };
    lattice_panels(
        &dir.join("tiny.png"),
        "long figure title",
        &[panel],
        3,
        &pal,
        1,
    )
    .unwrap();
    let (w, _, _) = decode_png(&dir.join("tiny.png"));
    assert_eq!(w, 1 + 2 * 10);
    let chart = Chart {
        title: "t".into(),
        series: vec![Series {
            label: "s".into(),
            x: vec![1e-300, 1e300, f64::INFINITY],
            y: vec![-1e308, 1e308, 0.0],
            points: true,
        }],
        ..Chart::default()
    };
    line_charts(
        &dir.join("small.png"),
        "",
        std::slice::from_ref(&chart),
        1,
        (64, 64),
    )
    .unwrap();
    let log = Chart {
        log_x: true,
        log_y: true,
        ..chart
    };
    line_charts(&dir.join("log.png"), "", &[log], 4, (64, 64)).unwrap();
    // Too large a figure is refused, not allocated.
    let many = vec![Chart::default(); 1000];
    let err = line_charts(&dir.join("many.png"), "", &many, 1, (4000, 4000)).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "chart_px"));
}

#[test]
fn palettes_cycle_extra_classes() {
    let p = Palette::default();
    assert_eq!(p.colors.len(), 11);
    assert_eq!(p.color(3), p.colors[3]);
    assert_eq!(p.color(11), p.colors[3]);
    assert_eq!(p.color(12), p.colors[4]);
    let short = Palette {
        colors: vec![RGBColor(1, 2, 3), RGBColor(4, 5, 6)],
    };
    assert_eq!(short.color(7), RGBColor(4, 5, 6));
    for p in [Palette::flame(), Palette::solid(), Palette::crystal()] {
        assert!(p.colors.len() >= 3);
        assert_ne!(p.colors[0], p.colors[1]);
        assert_ne!(p.colors[1], p.colors[2]);
    }
    assert_eq!(Palette::solid().colors[0], RGBColor(135, 206, 235));
}

#[test]
fn lattice_panels_png_has_requested_layout() {
    let dir = out_dir("panels");
    let path = dir.join("panels.png");
    let panels = vec![
        Panel {
            title: "square".into(),
            field: sample_field(60, 40, false),
        },
        Panel {
            title: "hexagonal".into(),
            field: sample_field(60, 40, true),
        },
        Panel {
            title: "third".into(),
            field: sample_field(30, 30, false),
        },
    ];
    lattice_panels(&path, "Test figure", &panels, 2, &Palette::flame(), 200).unwrap();
    let (w, h, img) = decode_png(&path);
    // Two columns of 200-pixel boxes plus gaps; two rows.
    assert_eq!(w, 2 * (200 + 10) + 10);
    assert!(h > 2 * 130, "height {h}");
    assert_eq!(img.len(), (w * h * 3) as usize);
    // Some pixels carry the flame palette's burnt colour, and text (dark pixels) exists in the
    // title strip at the top.
    let burnt = rgb(Palette::flame().colors[2]);
    assert!(img.chunks(3).any(|p| p == burnt));
    let title_rows = &img[..(w * 20 * 3) as usize];
    assert!(
        title_rows
            .chunks(3)
            .any(|p| p[0] < 100 && p[1] < 100 && p[2] < 100)
    );
    // No temporary file is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name() != "panels.png")
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn lattice_panels_rejects_bad_input() {
    let dir = out_dir("panels_bad");
    let path = dir.join("bad.png");
    let pal = Palette::default();
    let ok = Panel {
        title: "ok".into(),
        field: sample_field(4, 4, false),
    };
    let err = lattice_panels(&path, "t", &[], 2, &pal, 100).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "panels"));
    let err = lattice_panels(&path, "t", std::slice::from_ref(&ok), 0, &pal, 100).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "cols"));
    let err = lattice_panels(&path, "t", std::slice::from_ref(&ok), 1, &pal, 0).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "panel_px"));
    let zero = Panel {
        title: "zero".into(),
        field: CellField::new(0, 5, true),
    };
    let err = lattice_panels(&path, "t", &[ok.clone(), zero], 2, &pal, 100).unwrap_err();
    assert!(
        matches!(err, PlotError::InvalidInput { ref name, .. } if name == "panels[1].field.nx"),
        "{err}"
    );
    let short = Panel {
        title: "short".into(),
        field: CellField {
            nx: 3,
            ny: 3,
            hex: false,
            states: vec![0; 8],
        },
    };
    let err = lattice_panels(&path, "t", &[short], 1, &pal, 100).unwrap_err();
    assert!(err.to_string().contains("panels[0].field.states"), "{err}");
    assert!(!path.exists());
}

#[test]
fn gif_has_all_frames() {
    let dir = out_dir("gif");
    let path = dir.join("anim.gif");
    let pal = Palette::crystal();
    let mut gif = GifWriter::create(&path, 30, 20, true, 120, &pal, 5).unwrap();
    let (w, h) = gif.size();
    assert_eq!(w, 120);
    let mut field = CellField::new(30, 20, true);
    for k in 0..3 {
        for x in 0..30 {
            field.states[k * 30 + x] = 2;
        }
        gif.add_frame(&field).unwrap();
    }
    assert_eq!(gif.frames(), 3);
    // A field of another size is refused.
    assert!(gif.add_frame(&CellField::new(10, 10, true)).is_err());
    assert!(!path.exists(), "written only at finish");
    gif.finish().unwrap();

    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(File::open(&path).unwrap()).unwrap();
    assert_eq!((u32::from(dec.width()), u32::from(dec.height())), (w, h));
    let mut frames = Vec::new();
    while let Some(frame) = dec.read_next_frame().unwrap() {
        assert_eq!(frame.delay, 5);
        frames.push(frame.buffer.to_vec());
    }
    assert_eq!(frames.len(), 3);
    // The frames differ, and the bottom-middle pixel of the last frame is crystal (state 2).
    assert_ne!(frames[0], frames[2]);
    let k = (((h - 3) * w + w / 2) * 4) as usize;
    assert_eq!(&frames[2][k..k + 3], &rgb(pal.colors[2]));
}

#[test]
fn gif_rejects_bad_input() {
    let dir = out_dir("gif_bad");
    let path = dir.join("bad.gif");
    let pal = Palette::default();
    for (nx, ny, max_px, name) in [(0, 5, 100, "nx"), (5, 0, 100, "ny"), (5, 5, 0, "max_px")] {
        let err = GifWriter::create(&path, nx, ny, false, max_px, &pal, 10).unwrap_err();
        assert!(
            matches!(err, PlotError::InvalidInput { name: ref n, .. } if n == name),
            "{err}"
        );
    }
    let gif = GifWriter::create(&path, 5, 5, false, 50, &pal, 10).unwrap();
    assert!(gif.finish().is_err());
    assert!(!path.exists());
}

#[test]
fn charts_render_with_nans_and_log_zeros() {
    let dir = out_dir("charts");
    let path = dir.join("charts.png");
    let t: Vec<f64> = (0..50).map(f64::from).collect();
    let charts = vec![
        Chart {
            title: "linear with NaN".into(),
            x_label: "time".into(),
            y_label: "height".into(),
            series: vec![
                Series {
                    label: "mean".into(),
                    x: t.clone(),
                    y: t.iter()
                        .map(|&v| if v == 20.0 { f64::NAN } else { v.sqrt() })
                        .collect(),
                    points: true,
                },
                Series {
                    label: "all NaN".into(),
                    x: t.clone(),
                    y: vec![f64::NAN; 50],
                    points: false,
                },
            ],
            log_x: false,
            log_y: false,
        },
        Chart {
            title: "log-log with zeros".into(),
            x_label: "L".into(),
            y_label: "width".into(),
            series: vec![Series {
                label: "w(L)".into(),
                x: t.clone(),
                y: t.iter().map(|&v| v.powf(0.33)).collect(),
                points: false,
            }],
            log_x: true,
            log_y: true,
        },
        Chart {
            title: "empty".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![],
            log_x: false,
            log_y: true,
        },
    ];
    line_charts(&path, "Charts", &charts, 2, (320, 240)).unwrap();
    let (w, h, img) = decode_png(&path);
    assert_eq!(w, 640);
    assert!(h > 480);
    // Series colours from Palette99 are present.
    let c0 = <plotters::style::Palette99 as plotters::style::Palette>::pick(0).to_rgba();
    assert!(img.chunks(3).any(|p| p == [c0.0, c0.1, c0.2]));

    let err = line_charts(&path, "t", &[], 1, (320, 240)).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "charts"));
    let err = line_charts(&path, "t", &charts, 0, (320, 240)).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "cols"));
    let err = line_charts(&path, "t", &charts, 1, (0, 240)).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { ref name, .. } if name == "chart_px"));
}

#[test]
fn large_panels_draw_quickly_in_release() {
    // 4 panels of 1000 x 1000 cells; the timing bound applies to optimised builds only.
    let dir = out_dir("large");
    let panels: Vec<Panel> = (0..4)
        .map(|k| Panel {
            title: format!("panel {k}"),
            field: sample_field(1000, 1000, k % 2 == 1),
        })
        .collect();
    let start = std::time::Instant::now();
    lattice_panels(
        &dir.join("large.png"),
        "Large",
        &panels,
        2,
        &Palette::default(),
        500,
    )
    .unwrap();
    let secs = start.elapsed().as_secs_f64();
    if !cfg!(debug_assertions) {
        assert!(secs < 1.0, "took {secs} s");
    }
}
