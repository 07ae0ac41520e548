//! lancer's denoiser: Intel Open Image Denoise's trained U-Net (OIDN 2.x, the `rt` filter in
//! HDR mode, quality "high"), run on the CPU by code of ours.
//!
//! The weights are OIDN's own (Apache-2.0, see `weights/README.md` for where they come from);
//! the network, its input/output transfer, the autoexposure and the tiling follow OIDN's
//! source, so the result is OIDN's up to float rounding. Three networks: colour alone,
//! colour + albedo, colour + albedo + normal.
//!
//! Images are interleaved RGB `f32`, row-major, `width × height × 3`.

pub mod conv;
pub mod tensor;
pub mod transfer;
pub mod tza;
pub mod unet;

use rayon::prelude::*;
use std::sync::OnceLock;
use transfer::{Transfer, albedo_in, normal_in};
use unet::UNet;

/// OIDN's `rt_hdr` weights (colour only).
static RT_HDR: &[u8] = include_bytes!("../weights/rt_hdr.tza");
/// OIDN's `rt_hdr_alb` weights (colour + albedo).
static RT_HDR_ALB: &[u8] = include_bytes!("../weights/rt_hdr_alb.tza");
/// OIDN's `rt_hdr_alb_nrm` weights (colour + albedo + normal).
static RT_HDR_ALB_NRM: &[u8] = include_bytes!("../weights/rt_hdr_alb_nrm.tza");

/// The Open Image Denoise release the weights were taken from.
pub const OIDN_VERSION: &str = "2.5.1";

/// Spatial alignment of a tile (four 2× poolings) and of its position.
const TILE_ALIGN: usize = 16;
/// Pixels of context a tile takes from each neighbour: OIDN's receptive field 174 / 2,
/// rounded up to the alignment.
pub const TILE_OVERLAP: usize = 96;

/// Why an image could not be denoised.
#[derive(Debug, thiserror::Error)]
pub enum DenoiseError {
    /// An input's length is not width × height × 3, or the image is empty.
    #[error("{0}: {1} floats, expected {2} ({3}x{4} RGB)")]
    Size(&'static str, usize, usize, usize, usize),
    /// OIDN has no network for a normal without an albedo.
    #[error("a normal image needs an albedo image too (OIDN has no colour + normal network)")]
    NormalWithoutAlbedo,
    /// The built-in weights could not be read (a corrupted build).
    #[error(transparent)]
    Net(#[from] unet::NetError),
}

/// Tiling limits.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Largest tile, in pixels (the activations take about 860 bytes per tile pixel:
    /// [`unet::Workspace`]).
    pub max_tile_pixels: usize,
    /// Smallest tile side OIDN cuts to (768).
    pub min_tile_dim: usize,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            max_tile_pixels: 1024 * 1024,
            min_tile_dim: 768,
        }
    }
}

/// Which auxiliary images go with the colour (each has its own network).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inputs {
    /// Colour only.
    Color,
    /// Colour and albedo.
    ColorAlbedo,
    /// Colour, albedo and normal.
    ColorAlbedoNormal,
}

/// The network for a set of inputs, parsed once.
pub fn network(inputs: Inputs) -> Result<&'static UNet, DenoiseError> {
    static NETS: [OnceLock<UNet>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let (slot, blob) = match inputs {
        Inputs::Color => (&NETS[0], RT_HDR),
        Inputs::ColorAlbedo => (&NETS[1], RT_HDR_ALB),
        Inputs::ColorAlbedoNormal => (&NETS[2], RT_HDR_ALB_NRM),
    };
    if let Some(n) = slot.get() {
        return Ok(n);
    }
    let net = UNet::from_tza(blob)?;
    Ok(slot.get_or_init(|| net))
}

/// Denoises an HDR image with default tiling: [`denoise_with`].
pub fn denoise(
    color: &[f32],
    albedo: Option<&[f32]>,
    normal: Option<&[f32]>,
    width: usize,
    height: usize,
) -> Result<Vec<f32>, DenoiseError> {
    denoise_with(&Options::default(), color, albedo, normal, width, height)
}

/// The tiles of an image: OIDN's `UNetFilter::init` search. Start from one tile of the
/// image rounded up to 16; while a tile has more than `max_tile_pixels`, cut the longer
/// side (rows first when it is longer) into one more tile, each tile
/// ⌈(H + 2·overlap·n)/(n+1)⌉ rounded up to 16 (at least `min_tile_dim`), the count then
/// ⌈(H − 2·overlap)/(tile − 2·overlap)⌉.
/// Returns (tile height, tile width, tiles down, tiles across).
pub fn tile_plan(width: usize, height: usize, opts: &Options) -> (usize, usize, usize, usize) {
    let (h, w) = (height as i64, width as i64);
    let a = TILE_ALIGN as i64;
    let ov2 = 2 * TILE_OVERLAP as i64;
    let round_up = |v: i64| (v + a - 1).div_euclid(a) * a;
    let ceil_div = |x: i64, y: i64| (x + y - 1).div_euclid(y);
    let (mut th, mut tw, mut nh, mut nw) = (round_up(h), round_up(w), 1i64, 1i64);
    let min_tile = round_up(opts.min_tile_dim.max(2 * ov2 as usize) as i64);
    while th * tw > opts.max_tile_pixels as i64 {
        if th > min_tile && th > tw {
            let new = ceil_div(h + ov2 * nh, nh + 1);
            th = round_up(new).clamp(min_tile, th - a);
            nh = ceil_div(h - ov2, th - ov2).max(1);
        } else if tw > min_tile {
            let new = ceil_div(w + ov2 * nw, nw + 1);
            tw = round_up(new).clamp(min_tile, tw - a);
            nw = ceil_div(w - ov2, tw - ov2).max(1);
        } else {
            break;
        }
    }
    (th as usize, tw as usize, nh as usize, nw as usize)
}

/// One axis of a tile: where it reads and writes (OIDN's `UNetFilter::execute`).
#[derive(Clone, Copy, Debug)]
struct Span {
    /// First image pixel read.
    src: usize,
    /// Pixels read.
    len: usize,
    /// Where they go in the tile (aligned to the tile's end, rounded to 16).
    align: usize,
    /// Pixels of context before the written part.
    begin: usize,
    /// Pixels written.
    out: usize,
}

fn spans(size: usize, tile: usize, count: usize) -> Vec<Span> {
    (0..count)
        .map(|i| {
            // (a single tile may be narrower than two overlaps)
            let src = if i == 0 {
                0
            } else {
                i * (tile - 2 * TILE_OVERLAP)
            };
            let begin = if i > 0 { TILE_OVERLAP } else { 0 };
            let end = if i + 1 < count { TILE_OVERLAP } else { 0 };
            let len = (size - src).min(tile);
            let align = tile - len.div_ceil(TILE_ALIGN) * TILE_ALIGN;
            Span {
                src,
                len,
                align,
                begin,
                out: len - begin - end,
            }
        })
        .collect()
}

/// Writes channel `k` of `img` (interleaved RGB, `width` pixels a row), mapped by `f`, into
/// the tile's plane `p` (row stride `stride`) where the spans `(rows, columns)` place it.
fn fill_plane(
    p: &mut [f32],
    stride: usize,
    img: &[f32],
    width: usize,
    k: usize,
    (sy, sx): (Span, Span),
    f: impl Fn(f32) -> f32,
) {
    for y in 0..sy.len {
        let row = &mut p[(sy.align + y + 1) * stride + sx.align + 1..][..sx.len];
        let src = &img[((sy.src + y) * width + sx.src) * 3..][..sx.len * 3];
        for (o, px) in row.iter_mut().zip(src.chunks_exact(3)) {
            *o = f(px[k]);
        }
    }
}

/// Denoises an HDR image (interleaved RGB, `width × height`) with OIDN's `rt` network for
/// the given auxiliary images: autoexposure of the colour, PU transfer, the U-Net on each
/// tile (with `TILE_OVERLAP` pixels of context), the inverse transfer.
pub fn denoise_with(
    opts: &Options,
    color: &[f32],
    albedo: Option<&[f32]>,
    normal: Option<&[f32]>,
    width: usize,
    height: usize,
) -> Result<Vec<f32>, DenoiseError> {
    let n = width * height * 3;
    for (name, img) in [
        ("colour", Some(color)),
        ("albedo", albedo),
        ("normal", normal),
    ] {
        if let Some(img) = img
            && (img.len() != n || n == 0)
        {
            return Err(DenoiseError::Size(name, img.len(), n, width, height));
        }
    }
    let inputs = match (albedo, normal) {
        (None, None) => Inputs::Color,
        (Some(_), None) => Inputs::ColorAlbedo,
        (Some(_), Some(_)) => Inputs::ColorAlbedoNormal,
        (None, Some(_)) => return Err(DenoiseError::NormalWithoutAlbedo),
    };
    let net = network(inputs)?;
    let transfer = Transfer::new(transfer::autoexposure(color, width, height));
    let (th, tw, nh, nw) = tile_plan(width, height, opts);
    let mut out = vec![0.0f32; n];
    let mut ws = net.workspace(th, tw);
    let off = net.skip0_offset();
    for sy in spans(height, th, nh) {
        for sx in spans(width, tw, nw) {
            let x0 = &mut ws.x0;
            let (plane, stride) = (x0.plane(), x0.stride());
            // Input: transfer each channel into its plane (zeros around the image data).
            x0.data[off * plane..(off + net.input_channels) * plane]
                .par_chunks_mut(plane)
                .enumerate()
                .for_each(|(c, p)| {
                    p.fill(0.0);
                    let k = c % 3;
                    match c / 3 {
                        0 => fill_plane(p, stride, color, width, k, (sy, sx), |v| {
                            transfer.forward(v)
                        }),
                        1 => fill_plane(p, stride, albedo.unwrap(), width, k, (sy, sx), albedo_in),
                        _ => fill_plane(p, stride, normal.unwrap(), width, k, (sy, sx), normal_in),
                    }
                });
            let y = net.run(&mut ws);
            // Output: the tile's inner part, back through the inverse transfer.
            let rows = &mut out[(sy.src + sy.begin) * width * 3..][..sy.out * width * 3];
            rows.par_chunks_mut(width * 3)
                .enumerate()
                .for_each(|(r, row)| {
                    let ty = sy.align + sy.begin + r;
                    for x in 0..sx.out {
                        let tx = sx.align + sx.begin + x;
                        for c in 0..3 {
                            row[(sx.src + sx.begin + x) * 3 + c] =
                                transfer.inverse(y.at(c, ty, tx));
                        }
                    }
                });
        }
    }
    Ok(out)
}
