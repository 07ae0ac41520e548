//! A `.bsdf` file as the readers give it ([`MeasuredFile`]): its tables parsed and checked, plain
//! data; the scene build makes the sampling tables from it ([`super::MeasuredData`]).

use super::tensor::{Field, Tensor};
use crate::math::PI;
use std::collections::HashMap;
use std::fmt;
use std::sync::{Arc, Mutex, OnceLock, Weak};

/// Largest number of table entries a file may hold (each table together), 2²⁸ (1 GiB of f32).
pub const MAX_ENTRIES: usize = 1 << 28;

/// One table of a file: its values (row-major) and its size along each dimension.
#[derive(Clone, PartialEq)]
pub struct Table {
    /// The values, the last dimension fastest.
    pub values: Vec<f32>,
    /// Size along each dimension.
    pub shape: Vec<usize>,
}

/// A measured BRDF's tables as read from its file, checked (every size consistent, every
/// value finite, the parameter nodes ascending) so that building its sampling tables cannot
/// fail.
#[derive(Clone, PartialEq)]
pub struct MeasuredFile {
    /// Where it was read from (for messages).
    pub name: String,
    /// The file's `description` text, if any.
    pub description: String,
    /// A hash of the file's bytes and their number: two files with the same key hold the same
    /// BRDF.
    pub content_key: (u64, usize),
    /// At most two φᵢ nodes: the tables depend on φm − φo only.
    pub isotropic: bool,
    /// The θᵢ nodes (rad).
    pub theta_i: Vec<f32>,
    /// The φᵢ nodes (rad).
    pub phi_i: Vec<f32>,
    /// The wavelengths of `spectra`, nm (empty for an RGB-only file).
    pub wavelengths: Vec<f32>,
    /// D(ωm) over the unit square (2 dimensions).
    pub ndf: Table,
    /// σ(ωo) over the unit square (2 dimensions).
    pub sigma: Table,
    /// The visible normals, [φᵢ, θᵢ, n, n].
    pub vndf: Table,
    /// The luminance over the sample square, [φᵢ, θᵢ, n, n].
    pub luminance: Table,
    /// The reflectance part per wavelength, [φᵢ, θᵢ, λ, n, n].
    pub spectra: Option<Table>,
    /// The reflectance part per linear sRGB channel, [φᵢ, θᵢ, 3, n, n] (absent when the
    /// file gives only `spectra`; with neither, which the reader refuses, the BRDF is black).
    pub rgb: Option<Table>,
}

impl fmt::Debug for MeasuredFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "MeasuredFile {{ name: {:?}, content_key: ({:#018x}, {}) }}",
            self.name, self.content_key.0, self.content_key.1
        )
    }
}

/// FNV-1a of a byte string.
fn fnv1a(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| {
        (h ^ x as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// Reads a field's floats, checking its rank and that every value is finite (and ≥ 0 when
/// `nonnegative`).
fn floats(
    t: &Tensor,
    name: &str,
    rank: usize,
    nonnegative: bool,
) -> Result<(Vec<f32>, Vec<usize>), String> {
    let f = t
        .fields
        .get(name)
        .ok_or_else(|| format!("the file has no \"{name}\" field"))?;
    floats_of(f, name, rank, nonnegative)
}

fn floats_of(
    f: &Field,
    name: &str,
    rank: usize,
    nonnegative: bool,
) -> Result<(Vec<f32>, Vec<usize>), String> {
    if f.shape.len() != rank {
        return Err(format!(
            "field \"{name}\" has shape {:?}; it needs {rank} dimensions",
            f.shape
        ));
    }
    let v = f.to_f32().ok_or_else(|| {
        format!(
            "field \"{name}\" holds {:?} values; it needs 32- or 64-bit floats",
            f.dtype
        )
    })?;
    if let Some(i) = v
        .iter()
        .position(|x| !x.is_finite() || (nonnegative && *x < 0.0))
    {
        return Err(format!("field \"{name}\" holds {} at index {i}", v[i]));
    }
    Ok((v, f.shape.clone()))
}

/// Checks that a 1D parameter field's nodes ascend strictly.
fn ascending(name: &str, v: &[f32]) -> Result<(), String> {
    if v.is_empty() {
        return Err(format!("field \"{name}\" is empty"));
    }
    if v.windows(2).any(|w| w[1] <= w[0]) {
        return Err(format!("field \"{name}\" does not increase: {v:?}"));
    }
    Ok(())
}

/// Checks `shape` against what is `want`ed (`None` = any size ≥ 2), naming the field.
fn check_shape(name: &str, shape: &[usize], want: &[Option<usize>]) -> Result<(), String> {
    let ok = shape.len() == want.len()
        && shape.iter().zip(want).all(|(&s, w)| match w {
            Some(n) => s == *n,
            None => s >= 2,
        });
    if ok {
        return Ok(());
    }
    let want: Vec<String> = want
        .iter()
        .map(|w| w.map_or("n ≥ 2".to_string(), |n| n.to_string()))
        .collect();
    Err(format!(
        "field \"{name}\" has shape {shape:?}; [{}] is needed",
        want.join(", ")
    ))
}
impl MeasuredFile {
    /// The BRDF in the bytes of a `.bsdf` file; `name` names it in messages. Errors say what
    /// is wrong with the file.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<MeasuredFile, String> {
        let t = Tensor::parse(bytes)?;
        let total: usize = t
            .fields
            .values()
            .map(|f| f.shape.iter().product::<usize>())
            .sum();
        if total > MAX_ENTRIES {
            return Err(format!(
                "the tables hold {total} values (at most {MAX_ENTRIES} are read)"
            ));
        }
        let (theta_i, _) = floats(&t, "theta_i", 1, false)?;
        let (phi_i, _) = floats(&t, "phi_i", 1, false)?;
        ascending("theta_i", &theta_i)?;
        ascending("phi_i", &phi_i)?;
        let (np, nt) = (Some(phi_i.len()), Some(theta_i.len()));
        let isotropic = phi_i.len() <= 2;
        if !isotropic {
            let span = phi_i[phi_i.len() - 1] - phi_i[0];
            let reduction = (2.0 * PI / span).round();
            if reduction != 1.0 {
                return Err(format!(
                    "phi_i spans {span} rad, a symmetry reduction of {reduction}; only full \
                     circles (reduction 1) are supported, as in pbrt-v4"
                ));
            }
        }
        let table = |name: &str, rank: usize, nonnegative: bool| {
            floats(&t, name, rank, nonnegative).map(|(values, shape)| Table { values, shape })
        };
        let ndf = table("ndf", 2, true)?;
        check_shape("ndf", &ndf.shape, &[None, None])?;
        let sigma = table("sigma", 2, true)?;
        check_shape("sigma", &sigma.shape, &[None, None])?;
        let vndf = table("vndf", 4, true)?;
        check_shape("vndf", &vndf.shape, &[np, nt, None, None])?;
        let luminance = table("luminance", 4, true)?;
        let ls = &luminance.shape;
        check_shape("luminance", ls, &[np, nt, None, None])?;
        let n = ls[3];
        if ls[2] != n {
            return Err(format!(
                "field \"luminance\" has shape {ls:?}; its last two sizes must be equal"
            ));
        }
        let mut spectra = None;
        let mut wavelengths = Vec::new();
        if t.fields.contains_key("spectra") {
            let (w, _) = floats(&t, "wavelengths", 1, false)?;
            ascending("wavelengths", &w)?;
            let s = table("spectra", 5, false)?;
            check_shape(
                "spectra",
                &s.shape,
                &[np, nt, Some(w.len()), Some(n), Some(n)],
            )?;
            spectra = Some(s);
            wavelengths = w;
        }
        let rgb = if t.fields.contains_key("rgb") {
            let s = table("rgb", 5, false)?;
            check_shape("rgb", &s.shape, &[np, nt, Some(3), Some(n), Some(n)])?;
            Some(s)
        } else if spectra.is_some() {
            None
        } else {
            return Err("the file has neither a \"spectra\" nor an \"rgb\" field".into());
        };
        Ok(MeasuredFile {
            name: name.to_string(),
            description: t
                .fields
                .get("description")
                .map(|f| String::from_utf8_lossy(&f.bytes).into_owned())
                .unwrap_or_default(),
            content_key: (fnv1a(bytes), bytes.len()),
            isotropic,
            theta_i,
            phi_i,
            wavelengths,
            ndf,
            sigma,
            vndf,
            luminance,
            spectra,
            rgb,
        })
    }

    /// [`MeasuredFile::from_bytes`], shared: while a file's tables are held (by a scene
    /// description), reading the same bytes again gives the same tables, so that the
    /// materials naming one file share them (and the scene build makes its sampling tables
    /// once).
    pub fn shared(bytes: &[u8], name: &str) -> Result<Arc<MeasuredFile>, String> {
        type Cache = Mutex<HashMap<(u64, usize), Weak<MeasuredFile>>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let key = (fnv1a(bytes), bytes.len());
        let cache = CACHE.get_or_init(Default::default);
        if let Some(d) = cache
            .lock()
            .ok()
            .and_then(|c| c.get(&key).and_then(Weak::upgrade))
        {
            return Ok(d);
        }
        let d = Arc::new(Self::from_bytes(bytes, name)?);
        if let Ok(mut c) = cache.lock() {
            c.retain(|_, w| w.strong_count() > 0);
            c.insert(key, Arc::downgrade(&d));
        }
        Ok(d)
    }
}
