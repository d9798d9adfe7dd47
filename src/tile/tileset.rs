//! [`Tile`]: one toroidal ripple tile, its bed elevation and optionally one volume field, taken
//! from an in-process [`Ripple`] run ([`Tile::from_ripple`], [`tiles_from_run`]), from a ripple
//! NetCDF file ([`tiles_from_file`]) or given
//! directly ([`Tile::from_elevation`]); [`check_pool`] checks that tiles can share a mosaic.

use super::TileError;
use crate::ripple::output::{Field, volume_field, volume_levels};
use crate::ripple::{AcousticModel, Ripple, RippleParams};

/// A volume field of a tile on `(z, y, x)`: `nz x ny x nx` values, NaN above the bed.
#[derive(Clone, Debug, PartialEq)]
pub struct TileVolume {
    /// Which field.
    pub field: Field,
    /// Levels (automata from the substrate up).
    pub nz: usize,
    /// Values, z-major then y then x.
    pub data: Vec<f32>,
    /// The acoustic model of the run that made it (`acoustics`): density, sound speed and
    /// impedance depend on it, so a pool mixes none of two models.
    pub acoustics: AcousticModel,
}

/// One toroidal tile: `ny` rows of `nx` elevations (m), bins `bin_size` m.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// Bins along x.
    pub nx: usize,
    /// Bins along y.
    pub ny: usize,
    /// Bin size, m.
    pub bin_size: f64,
    /// Height of one automaton, m.
    pub layer_thickness: f64,
    /// Direction of the (dominant) flow that shaped the tile, degrees counter-clockwise from
    /// the tile's own +x axis (0 for a ripple run in the flow frame, whose x axis is that flow).
    pub current_angle: f64,
    /// Direction of the tile's +x axis, degrees counter-clockwise from east (the ripple run's
    /// `x_axis_direction_deg`: 0 in the grid frame, the flow's direction in the flow frame).
    pub x_axis_deg: f64,
    /// Bed elevation, m, row-major (`y * nx + x`).
    pub elevation: Vec<f32>,
    /// A volume field, where asked.
    pub volume: Option<TileVolume>,
    /// Where the tile comes from ("seed 3, step 2500", "run.nc, step 3000").
    pub label: String,
    /// The depth of sand of the ripple run that made it, m (`layers x layer_thickness`: its
    /// mean elevation, which the run conserves); `None` for a tile from a bare elevation grid.
    pub sand_depth: Option<f64>,
}

impl Tile {
    /// A tile from an elevation grid (row-major, `nx x ny`), no volume. Errors: zero sizes, a
    /// wrong length, a non-positive bin size, non-finite heights.
    pub fn from_elevation(
        nx: usize,
        ny: usize,
        bin_size: f64,
        elevation: Vec<f32>,
        label: impl Into<String>,
    ) -> Result<Tile, TileError> {
        let t = Tile {
            nx,
            ny,
            bin_size,
            layer_thickness: bin_size,
            current_angle: 0.0,
            x_axis_deg: 0.0,
            elevation,
            volume: None,
            sand_depth: None,
            label: label.into(),
        };
        t.validate()?;
        Ok(t)
    }

    /// The current state of a run as a tile, with the volume field `field` if asked.
    pub fn from_ripple(r: &Ripple, field: Option<Field>, label: impl Into<String>) -> Tile {
        let (nx, ny) = r.size();
        let p = r.params();
        let volume = field
            .filter(|f| *f != Field::Elevation)
            .map(|f| TileVolume {
                field: f,
                nz: volume_levels(r),
                data: volume_field(r, f, f32::NAN),
                acoustics: p.acoustics,
            });
        Tile {
            nx,
            ny,
            bin_size: p.bin_size,
            layer_thickness: p.layer_thickness,
            current_angle: p.lattice_flow_angle(),
            x_axis_deg: p.frame_angle(),
            elevation: r.elevation().iter().map(|&v| v as f32).collect(),
            volume,
            sand_depth: Some(p.layers as f64 * p.layer_thickness),
            label: label.into(),
        }
    }

    /// Checks sizes and values.
    pub fn validate(&self) -> Result<(), TileError> {
        if self.nx == 0 || self.ny == 0 {
            return Err(TileError::range(
                "tile size",
                format!("{}x{}", self.nx, self.ny),
                "at least 1x1 bins",
            ));
        }
        if self.elevation.len() != self.nx * self.ny {
            return Err(TileError::range(
                "tile elevation",
                format!("{} values", self.elevation.len()),
                format!("nx x ny = {} values", self.nx * self.ny),
            ));
        }
        if !(self.bin_size.is_finite() && self.bin_size > 0.0) {
            return Err(TileError::range("bin_size", self.bin_size, "> 0 m"));
        }
        if let Some(v) = self.elevation.iter().find(|v| !v.is_finite()) {
            return Err(TileError::range(
                "tile elevation",
                v,
                "finite heights (no NaN or infinity)",
            ));
        }
        if let Some(v) = &self.volume
            && v.data.len() != v.nz * self.nx * self.ny
        {
            return Err(TileError::range(
                "tile volume",
                format!("{} values", v.data.len()),
                format!("nz x ny x nx = {} values", v.nz * self.nx * self.ny),
            ));
        }
        Ok(())
    }

    /// The elevation at bin `(x, y)`, indices taken modulo the tile (toroidal).
    #[inline]
    pub fn at(&self, x: usize, y: usize) -> f32 {
        self.elevation[(y % self.ny) * self.nx + x % self.nx]
    }
}

/// Runs `p` once per seed of `seeds` and keeps a tile at each step of `steps` (every run goes to
/// the largest step); `field` adds that volume field to every tile. Tiles are ordered by seed,
/// then step. Every run goes to the largest step asked for, whatever `p.steps` says. Errors: no
/// seeds, no steps, or parameters the ripple model rejects.
pub fn tiles_from_run(
    p: &RippleParams,
    seeds: &[u64],
    steps: &[u64],
    field: Option<Field>,
    mut progress: impl FnMut(u64),
) -> Result<Vec<Tile>, TileError> {
    if seeds.is_empty() {
        return Err(TileError::range("seeds", "(none)", "at least one seed"));
    }
    if steps.is_empty() {
        return Err(TileError::range("snapshots", "(none)", "at least one step"));
    }
    let mut steps = steps.to_vec();
    steps.sort_unstable();
    steps.dedup();
    let last = *steps.last().unwrap_or(&0);
    let mut tiles = Vec::new();
    let mut done = 0;
    for &seed in seeds {
        let q = RippleParams { seed, ..p.clone() };
        let mut r = Ripple::new(&q)?;
        let mut k = 0;
        for i in 0..=last {
            if i > 0 {
                r.step();
                done += 1;
                progress(done);
            }
            if k < steps.len() && steps[k] == i {
                tiles.push(Tile::from_ripple(
                    &r,
                    field,
                    format!("seed {seed}, step {i}"),
                ));
                k += 1;
            }
        }
    }
    Ok(tiles)
}

/// The SHA-256 digest (64 hexadecimal digits) of the values of `tiles`, in order: each tile's
/// size, bin size, layer thickness, current and x-axis directions, elevations and volume field
/// (its name, levels and values), as little-endian bytes; not the labels. Pools with equal
/// digests lay equal mosaics; a tile file remade with other contents under the same name, or a
/// generated tile computed otherwise, changes it. It identifies the tiles of a Zarr store
/// written in parts ([`crate::tile::zarr::TILES_DIGEST`]).
pub fn digest(tiles: &[Tile]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    h.update(b"cellsurf tiles v1");
    h.update((tiles.len() as u64).to_le_bytes());
    for t in tiles {
        h.update((t.nx as u64).to_le_bytes());
        h.update((t.ny as u64).to_le_bytes());
        for v in [t.bin_size, t.layer_thickness, t.current_angle, t.x_axis_deg] {
            h.update(v.to_le_bytes());
        }
        let bytes = |v: &[f32]| -> Vec<u8> { v.iter().flat_map(|x| x.to_le_bytes()).collect() };
        h.update(bytes(&t.elevation));
        match &t.volume {
            None => h.update([0u8]),
            Some(v) => {
                h.update([1u8]);
                h.update(v.field.name().as_bytes());
                h.update((v.nz as u64).to_le_bytes());
                h.update(bytes(&v.data));
            }
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Checks that the tiles of a pool can share a mosaic: at least one, each valid, all with the
/// size, bin size, x axis and (for tiles of ripple runs) depth of sand of the first and, when they carry volumes, its layer thickness, field and (for density, sound
/// speed and impedance) acoustic model.
pub fn check_pool(tiles: &[Tile]) -> Result<(), TileError> {
    let first = tiles
        .first()
        .ok_or_else(|| TileError::range("tiles", "(none)", "at least one tile"))?;
    for (i, t) in tiles.iter().enumerate() {
        t.validate()?;
        let bad = |reason: String| TileError::Mismatch {
            index: i,
            label: t.label.clone(),
            reason,
        };
        if (t.nx, t.ny) != (first.nx, first.ny) {
            return Err(bad(format!(
                "size {}x{} bins, first {}x{}",
                t.nx, t.ny, first.nx, first.ny
            )));
        }
        let turn = (t.x_axis_deg - first.x_axis_deg).rem_euclid(360.0);
        if turn > 1e-9 && turn < 360.0 - 1e-9 {
            return Err(bad(format!(
                "x axis at {} deg from east, first at {} deg (ripple runs in the flow frame turn \
                 their lattice with the flow: run the tiles with one flow direction, or with \
                 frame = grid)",
                t.x_axis_deg, first.x_axis_deg
            )));
        }
        if (t.bin_size - first.bin_size).abs() > 1e-9 * first.bin_size {
            return Err(bad(format!(
                "bin size {} m, first {} m",
                t.bin_size, first.bin_size
            )));
        }
        match (&t.volume, &first.volume) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                if a.field != b.field {
                    return Err(bad(format!(
                        "volume field {}, first {}",
                        a.field.name(),
                        b.field.name()
                    )));
                }
                if (t.layer_thickness - first.layer_thickness).abs() > 1e-9 * first.layer_thickness
                {
                    return Err(bad(format!(
                        "layer thickness {} m, first {} m",
                        t.layer_thickness, first.layer_thickness
                    )));
                }
                let acoustic = matches!(
                    a.field,
                    Field::Density | Field::SoundSpeed | Field::Impedance
                );
                if acoustic && a.acoustics != b.acoustics {
                    return Err(bad(format!(
                        "{} of acoustics = {}, first of acoustics = {}",
                        a.field.name(),
                        a.acoustics.name(),
                        b.acoustics.name()
                    )));
                }
            }
            _ => return Err(bad("one has a volume field and the other not".into())),
        }
        // the sand's depth: a ripple run conserves its sand, so its tiles' mean elevation is
        // that depth; tiles of two depths would meet in steps at their seams
        if let (Some(dt), Some(df)) = (t.sand_depth, first.sand_depth)
            && (dt - df).abs() > 1e-9 * df.abs().max(dt.abs())
        {
            // (to the nanometre: 0.00186, not 0.0018599999999999999)
            let nm = |v: f64| (v * 1e9).round() / 1e9;
            let (dt, df) = (nm(dt), nm(df));
            return Err(bad(format!(
                "sand depth {dt} m (layers x layer_thickness), first {df} m (tiles of another \
                 depth of sand meet the others in steps at their seams: make the tiles with one \
                 --layers and --layer-thickness)"
            )));
        }
    }
    Ok(())
}

/// The tiles of a ripple NetCDF file ([`crate::ripple::input::read`]): one per snapshot step of
/// `steps` (default: the last snapshot), with the volume field `field` if asked. The file holds
/// the volume of its final state only, so a volume goes with the last snapshot alone. Errors
/// name the file, the step or the field that is missing.
pub fn tiles_from_file(
    path: &std::path::Path,
    steps: Option<&[u64]>,
    field: Option<Field>,
) -> Result<Vec<Tile>, TileError> {
    let f = crate::ripple::input::read(path)?;
    let name = path.display().to_string();
    // a 2-D section is one row: laid side by side its rows would repeat across the mosaic
    if f.ny == 1 {
        return Err(TileError::range(
            "tile",
            &name,
            format!(
                "a 3-D ripple field (this is a 2-D section of {} x 1 bins; tiles are 3-D \
                 fields, made with `cellsurf ripple --size NXxNY`, NY above 1)",
                f.nx
            ),
        ));
    }
    let last = f.times.len().checked_sub(1).ok_or_else(|| {
        TileError::range(
            "tile",
            &name,
            "a ripple file with at least one elevation snapshot",
        )
    })?;
    let picks: Vec<usize> = match steps {
        None => vec![last],
        Some(s) => s
            .iter()
            .map(|t| {
                f.times.iter().position(|x| x == t).ok_or_else(|| {
                    TileError::range(
                        "snapshots",
                        t,
                        format!("a snapshot step of {name}: {:?}", f.times),
                    )
                })
            })
            .collect::<Result<_, _>>()?,
    };
    let volume = match field.filter(|f| *f != Field::Elevation) {
        None => None,
        Some(fl) => {
            let data = f.field(fl).ok_or_else(|| {
                TileError::range(
                    "volume",
                    fl.name(),
                    format!("a volume field written in {name}"),
                )
            })?;
            if let Some(&i) = picks.iter().find(|&&i| i != last) {
                return Err(TileError::range(
                    "snapshots",
                    f.times[i],
                    format!(
                        "the last snapshot ({}) with a volume: {name} holds the final volume only",
                        f.times[last]
                    ),
                ));
            }
            Some(TileVolume {
                field: fl,
                nz: f.nz,
                data: data.to_vec(),
                acoustics: f.params.acoustics,
            })
        }
    };
    picks
        .into_iter()
        .map(|i| {
            let t = Tile {
                nx: f.nx,
                ny: f.ny,
                bin_size: f.bin_size,
                layer_thickness: f.layer_thickness,
                current_angle: f.params.lattice_flow_angle(),
                x_axis_deg: f.params.frame_angle(),
                elevation: f.elevation[i].clone(),
                volume: volume.clone(),
                label: format!("{name}, step {}", f.times[i]),
                sand_depth: Some(f.params.layers as f64 * f.params.layer_thickness),
            };
            t.validate()?;
            Ok(t)
        })
        .collect()
}
