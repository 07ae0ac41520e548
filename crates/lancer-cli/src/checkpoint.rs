//! Checkpoints: a render's film accumulators and finished units of work, with the options
//! that started it, so that `lancer render --resume FILE` can finish it exactly; and the
//! signal handling that writes one on SIGINT/SIGTERM (and SIGHUP, unless it is ignored).
//!
//! The file is a short text header, `key=value` lines, then the binary data:
//!
//! ```text
//! lancer-checkpoint 1
//! cwd=/folder/the/render/started/in
//! arg=<each argument given after `lancer render`, one per line>
//! hash=<scene hash, 16 hex digits>
//! film=x0,x1,y0,y1,width,height
//! units=<count>
//! splats=x0,x1,y0,y1,channels      (only for a film with splats)
//! aux=aux.W,aux.A.R,…,aux.Ns.Z      (only for a `--denoise` render's film)
//! end
//! <count bytes: 1 when that unit of work is done, else 0>
//! <per pixel, row-major: Σw·R, Σw·G, Σw·B, Σw as i64, samples as u32, little-endian>
//! <with splats: per pixel of their bounds, row-major, `channels` sums as i64>
//! <with aux: per pixel, row-major, the denoiser's sums named on the `aux` line as the u64
//!  bits of each f64>
//! ```
//!
//! The `aux` sums are those a split part keeps as its `lancer.aux.*` channels
//! ([`lancer::film::part::PART_AUX`], [`aux_bits`]): a `--denoise` render interrupted and
//! resumed gives back the very floating-point sums, so it ends with the uninterrupted
//! render's bytes.

use lancer::film::part::{PART_AUX, PartError, aux_bits, aux_film, set_aux_bits};
use lancer::film::splat::SplatPlane;
use lancer::film::{Film, PixelBounds, PixelSum};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

const MAGIC: &str = "lancer-checkpoint 1";

/// A render's saved state.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// Folder the render was started in (relative paths in `args` are relative to it).
    pub cwd: PathBuf,
    /// The arguments given after `lancer render`.
    pub args: Vec<String>,
    /// The scene hash ([`crate::split::scene_hash`]).
    pub scene_hash: u64,
    /// Which units of work are done, in the order of `lancer::render::work_units`.
    pub done: Vec<bool>,
    /// The film so far.
    pub film: Film,
}

/// Bytes of one pixel's sums in the file.
const PIXEL_BYTES: usize = 4 * 8 + 4;

/// Bytes of one pixel's denoiser's sums in the file.
const AUX_BYTES: usize = PART_AUX.len() * 8;

/// The `aux` line's value: the names of the denoiser's sums, in their order in the file.
fn aux_names() -> String {
    PART_AUX.join(",")
}

impl Checkpoint {
    /// Encodes the checkpoint (see the module documentation for the layout).
    pub fn encode(&self) -> Vec<u8> {
        let b = &self.film.bounds;
        let mut head = format!("{MAGIC}\ncwd={}\n", self.cwd.display());
        for a in &self.args {
            // A newline inside an argument would break the line structure; arguments with
            // one cannot name a scene or an option of ours anyway.
            head.push_str(&format!("arg={}\n", a.replace('\n', " ")));
        }
        head.push_str(&format!(
            "hash={:016x}\nfilm={},{},{},{},{},{}\nunits={}\n",
            self.scene_hash,
            b.x0,
            b.x1,
            b.y0,
            b.y1,
            self.film.full_width,
            self.film.full_height,
            self.done.len()
        ));
        if let Some(sp) = &self.film.splats {
            let b = &sp.bounds;
            head.push_str(&format!(
                "splats={},{},{},{},{}\n",
                b.x0, b.x1, b.y0, b.y1, sp.channels
            ));
        }
        let aux = self.film.gbuffer.as_ref().filter(|g| g.config.for_denoiser);
        if aux.is_some() {
            head.push_str(&format!("aux={}\n", aux_names()));
        }
        head.push_str("end\n");
        let mut out = head.into_bytes();
        out.extend(self.done.iter().map(|&d| d as u8));
        out.reserve(self.film.pixels.len() * PIXEL_BYTES);
        for p in &self.film.pixels {
            for v in [p.rgb[0], p.rgb[1], p.rgb[2], p.weight] {
                out.extend_from_slice(&v.to_le_bytes());
            }
            out.extend_from_slice(&p.samples.to_le_bytes());
        }
        if let Some(sp) = &self.film.splats {
            for v in &sp.sums {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        if let Some(g) = aux {
            out.reserve(g.pixels.len() * AUX_BYTES);
            for p in &g.pixels {
                for v in aux_bits(p) {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        out
    }

    /// Writes the checkpoint atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> Result<(), PartError> {
        lancer::image_io::write_atomic(path, &self.encode()).map_err(|source| PartError::Io {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Reads a checkpoint, checking its structure; errors name the file (and the header line).
    pub fn read(path: &Path) -> Result<Checkpoint, PartError> {
        let bytes = std::fs::read(path).map_err(|source| PartError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::decode(&bytes).map_err(|message| PartError::Format {
            path: path.to_path_buf(),
            message,
        })
    }

    /// Decodes the bytes of a checkpoint file.
    pub fn decode(bytes: &[u8]) -> Result<Checkpoint, String> {
        if !bytes.starts_with(format!("{MAGIC}\n").as_bytes()) {
            return Err(format!("not a lancer checkpoint (no '{MAGIC}' first line)"));
        }
        let mut pos = 0;
        let mut lines = Vec::new();
        loop {
            let Some(nl) = bytes[pos..].iter().position(|&b| b == b'\n') else {
                return Err("truncated header (no 'end' line)".into());
            };
            let line = std::str::from_utf8(&bytes[pos..pos + nl])
                .map_err(|_| format!("line {}: not text", lines.len() + 1))?;
            pos += nl + 1;
            if line == "end" {
                break;
            }
            lines.push(line.to_string());
        }
        let (mut cwd, mut args, mut hash, mut film, mut units) = (None, vec![], None, None, None);
        let (mut splats, mut aux) = (None, false);
        for (n, line) in lines.iter().enumerate().skip(1) {
            let bad = |what: &str| format!("line {}: bad {what} '{line}'", n + 1);
            let (k, v) = line.split_once('=').ok_or_else(|| bad("line"))?;
            // The comma-separated integers of a `film` or `splats` line.
            let ints = |what: &str| -> Result<Vec<i64>, String> {
                v.split(',')
                    .map(|x| x.parse())
                    .collect::<Result<_, _>>()
                    .map_err(|_| bad(what))
            };
            let rect = |x0: i64, x1: i64, y0: i64, y1: i64| PixelBounds {
                x0: x0 as i32,
                x1: x1 as i32,
                y0: y0 as i32,
                y1: y1 as i32,
            };
            match k {
                "cwd" => cwd = Some(PathBuf::from(v)),
                "arg" => args.push(v.to_string()),
                "hash" => hash = Some(u64::from_str_radix(v, 16).map_err(|_| bad("hash"))?),
                "units" => units = Some(v.parse::<usize>().map_err(|_| bad("unit count"))?),
                "film" => match ints("film")?[..] {
                    [x0, x1, y0, y1, w, h]
                        if x0 <= x1
                            && y0 <= y1
                            && (1..=1 << 20).contains(&w)
                            && (1..=1 << 20).contains(&h)
                            && x0 >= 0
                            && y0 >= 0
                            && x1 <= w
                            && y1 <= h =>
                    {
                        film = Some((rect(x0, x1, y0, y1), w as u32, h as u32));
                    }
                    _ => return Err(bad("film")),
                },
                // Only the plane's shape here: its sums are allocated once the data's length
                // has been checked against it (a damaged header must not ask for petabytes).
                "splats" => match ints("splats")?[..] {
                    [x0, x1, y0, y1, c]
                        if x0 <= x1
                            && y0 <= y1
                            && [x0, x1, y0, y1].iter().all(|v| (0..=1 << 20).contains(v))
                            && (1..=1024).contains(&c) =>
                    {
                        splats = Some((rect(x0, x1, y0, y1), c as usize));
                    }
                    _ => return Err(bad("splats")),
                },
                // The denoiser's sums: the part format's, in its order (a file of another
                // version of lancer with other sums is refused, not misread).
                "aux" if v == aux_names() => aux = true,
                "aux" => return Err(bad("aux")),
                _ => return Err(format!("line {}: unknown key '{k}'", n + 1)),
            }
        }
        let missing = |k: &str| format!("the header has no '{k}=' line");
        let (bounds, w, h) = film.ok_or_else(|| missing("film"))?;
        let units = units.ok_or_else(|| missing("units"))?;
        let npix = bounds.area() as usize;
        let splat_bytes = splats.map_or(0, |(b, c): (PixelBounds, usize)| {
            (b.area() as usize).saturating_mul(c).saturating_mul(8)
        });
        let aux_bytes = if aux {
            npix.saturating_mul(AUX_BYTES)
        } else {
            0
        };
        let expected = units
            .saturating_add(npix.saturating_mul(PIXEL_BYTES))
            .saturating_add(splat_bytes)
            .saturating_add(aux_bytes);
        if bytes.len() - pos != expected {
            return Err(format!(
                "{} bytes of data where {units} units, {npix} pixels, {splat_bytes} bytes of \
                 splats and {aux_bytes} of denoiser's sums need {expected}: the file is \
                 truncated or damaged",
                bytes.len() - pos
            ));
        }
        let done = bytes[pos..pos + units].iter().map(|&b| b != 0).collect();
        pos += units;
        let mut film = Film::new(w, h, bounds);
        let i64_at = |p: usize| i64::from_le_bytes(bytes[p..p + 8].try_into().unwrap());
        for px in film.pixels.iter_mut() {
            *px = PixelSum {
                rgb: [i64_at(pos), i64_at(pos + 8), i64_at(pos + 16)],
                weight: i64_at(pos + 24),
                samples: u32::from_le_bytes(bytes[pos + 32..pos + 36].try_into().unwrap()),
            };
            pos += PIXEL_BYTES;
        }
        if let Some((b, c)) = splats {
            let mut sp = SplatPlane::new(b, c);
            for v in sp.sums.iter_mut() {
                *v = i64_at(pos);
                pos += 8;
            }
            film.splats = Some(Box::new(sp));
        }
        if aux {
            // The samples per pixel are not known here: the render that continues the film
            // gives it the scene's configuration (`crate::denoise::prepare`).
            let mut g = aux_film(npix, 0);
            for p in g.pixels.iter_mut() {
                set_aux_bits(p, std::array::from_fn(|k| i64_at(pos + 8 * k) as u64));
                pos += AUX_BYTES;
            }
            film.gbuffer = Some(Box::new(g));
        }
        Ok(Checkpoint {
            cwd: cwd.ok_or_else(|| missing("cwd"))?,
            args,
            scene_hash: hash.ok_or_else(|| missing("hash"))?,
            done,
            film,
        })
    }
}

/// Set by the first SIGINT/SIGTERM.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// True once SIGINT or SIGTERM has arrived.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// Installs the SIGINT/SIGTERM/SIGHUP handler: the first signal asks the render to stop
/// handing out work (it then writes its image and checkpoint and exits with status 130); a
/// second one exits at once with status 130 (files are only ever replaced by rename, so none
/// is left half written). A SIGHUP ignored when lancer started (`nohup lancer render …`) stays
/// ignored: the render goes on after a hang-up. Installed once per process (a second call, from
/// a second run of [`crate::run`] in one process, keeps the first).
pub fn install_handler() -> Result<(), String> {
    static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();
    INSTALLED.get_or_init(install_handler_once).clone()
}

/// [`install_handler`]'s work.
fn install_handler_once() -> Result<(), String> {
    let hangup_ignored = hangup_ignored();
    ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: exiting without a checkpoint");
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: finishing the tiles in flight, then writing a checkpoint");
    })
    .map_err(|e| format!("cannot install the interrupt handler: {e}"))?;
    // ctrlc takes SIGHUP along with SIGTERM; give nohup's SIG_IGN back at once.
    if hangup_ignored {
        ignore_hangup();
    }
    Ok(())
}

/// True when SIGHUP is ignored (as `nohup` leaves it for the program it starts).
#[cfg(unix)]
pub fn hangup_ignored() -> bool {
    // SAFETY: with a null new action, sigaction only writes the current one into `old`, a
    // plain C struct for which all zeros is a valid value.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        libc::sigaction(libc::SIGHUP, std::ptr::null(), &mut old) == 0
            && old.sa_sigaction == libc::SIG_IGN
    }
}

/// Whether SIGHUP is ignored: never, where there is no SIGHUP.
#[cfg(not(unix))]
pub fn hangup_ignored() -> bool {
    false
}

#[cfg(unix)]
fn ignore_hangup() {
    // SAFETY: setting a signal's disposition to SIG_IGN involves no handler code.
    unsafe {
        libc::signal(libc::SIGHUP, libc::SIG_IGN);
    }
}

#[cfg(not(unix))]
fn ignore_hangup() {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkpoints_round_trip_and_damage_is_caught() {
        let b = PixelBounds {
            x0: 1,
            x1: 4,
            y0: 0,
            y1: 2,
        };
        let mut film = Film::new(5, 3, b);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            p.rgb = [i as i64 * -77, 1 << 50, 3];
            p.weight = i as i64 + 9;
            p.samples = i as u32;
        }
        let c = Checkpoint {
            cwd: PathBuf::from("/some/where"),
            args: vec!["scene.pbrt".into(), "--spp".into(), "16".into()],
            scene_hash: 0x0123_4567_89ab_cdef,
            done: vec![true, false, true, true],
            film,
        };
        let bytes = c.encode();
        assert_eq!(Checkpoint::decode(&bytes).unwrap(), c);
        let e = Checkpoint::decode(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
        let e = Checkpoint::decode(b"\x76\x2f\x31\x01 an EXR").unwrap_err();
        assert!(e.contains("not a lancer checkpoint"), "{e}");

        // A film with splats keeps them (over bounds of their own), bit for bit.
        let mut c2 = c.clone();
        let sb = PixelBounds {
            x0: 0,
            x1: 5,
            y0: 0,
            y1: 3,
        };
        let mut plane = SplatPlane::new(sb, 4);
        for (i, v) in plane.sums.iter_mut().enumerate() {
            *v = (i as i64 - 20) << 37 | 5;
        }
        c2.film.splats = Some(Box::new(plane));
        let bytes2 = c2.encode();
        assert_eq!(Checkpoint::decode(&bytes2).unwrap(), c2);
        assert!(Checkpoint::decode(&bytes2[..bytes2.len() - 8]).is_err());
        // A damaged splats line asking for a huge plane is an error, not an allocation.
        let line = b"splats=0,5,0,3,4\n";
        let at = bytes2.windows(line.len()).position(|w| w == line).unwrap();
        let mut huge = bytes2[..at].to_vec();
        huge.extend_from_slice(b"splats=0,1048576,0,1048576,1024\n");
        huge.extend_from_slice(&bytes2[at + line.len()..]);
        let e = Checkpoint::decode(&huge).unwrap_err();
        assert!(e.contains("truncated or damaged"), "{e}");
        // Without splats, the file is the one written before splats existed.
        assert!(!String::from_utf8_lossy(&bytes).contains("splats="));

        // A `--denoise` render's film keeps the denoiser's sums (the part format's, in its
        // order), every f64 bit for bit, beside the splats.
        let mut c3 = c2.clone();
        let mut g = aux_film(c3.film.pixels.len(), 0);
        for (i, p) in g.pixels.iter_mut().enumerate() {
            let v = |k: usize| (i * 7 + k) as f64 * -0.1 + 1e-300;
            set_aux_bits(p, std::array::from_fn(|k| v(k).to_bits()));
        }
        c3.film.gbuffer = Some(Box::new(g));
        let bytes3 = c3.encode();
        let back = Checkpoint::decode(&bytes3).unwrap();
        assert_eq!(back, c3);
        let bits = |c: &Checkpoint| -> Vec<[u64; 7]> {
            let g = c.film.gbuffer.as_ref().unwrap();
            g.pixels.iter().map(aux_bits).collect()
        };
        assert_eq!(bits(&back), bits(&c3));
        assert!(String::from_utf8_lossy(&bytes3).contains(&format!("aux={}\n", aux_names())));
        let e = Checkpoint::decode(&bytes3[..bytes3.len() - 8]).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
        // Sums of another kind are refused, not misread.
        let mut other = bytes3.clone();
        let at = other.windows(10).position(|w| w == b"aux=aux.W,").unwrap();
        other[at + 8] = b'V';
        let e = Checkpoint::decode(&other).unwrap_err();
        assert!(e.contains("bad aux"), "{e}");
        // Without the denoiser's sums, no `aux` line.
        assert!(!String::from_utf8_lossy(&bytes2).contains("aux="));
    }
}
