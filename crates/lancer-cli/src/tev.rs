//! Streaming the image as it converges to the [tev](https://github.com/Tom94/tev) HDR viewer
//! over TCP (`--display-server HOST:PORT`), in tev's IPC protocol.
//!
//! Every packet is little-endian: `u32` total length (the 4 length bytes included), `u8` type,
//! then the fields; strings end with a NUL byte, booleans are one byte. lancer sends
//! - `CreateImage` (type 4): grab focus, image name, width `i32`, height `i32`, channel count
//!   `i32`, channel names;
//! - `UpdateImage` version 3 (type 6): grab focus, image name, channel count `i32`, channel
//!   names, x, y, width, height (`i32`), per-channel offset and stride (`i64`, in floats), then
//!   the `f32` pixels. Channel c of pixel i is at float `offset[c] + i·stride[c]`; lancer sends
//!   RGB interleaved: offsets 0, 1, 2 and stride 3.
//!
//! The stream runs on its own thread, reading from the [`LiveImage`]: rendering never waits for
//! the network, and a viewer that cannot be reached is a warning, not an error.

use crate::live::LiveImage;
use lancer::film::PixelBounds;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// tev's packet type numbers.
pub mod packet_type {
    /// Create an image with given size and channels.
    pub const CREATE_IMAGE: u8 = 4;
    /// Update a rectangle of an image, channels with offset and stride.
    pub const UPDATE_IMAGE_V3: u8 = 6;
}

/// The channels lancer sends.
pub const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// Largest number of floats in one update packet (4 MiB of pixels): a big final image goes out
/// in strips of rows.
pub const MAX_FLOATS_PER_PACKET: usize = 1 << 20;

/// A packet being written: fields appended little-endian, the length patched in at the end.
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8) -> Packet {
        let mut b = Vec::with_capacity(64);
        b.extend_from_slice(&[0; 4]);
        b.push(kind);
        Packet(b)
    }
    fn bool(&mut self, v: bool) {
        self.0.push(v as u8);
    }
    fn str(&mut self, s: &str) {
        // A NUL inside a name would end it early on the other side: drop any.
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
    }
    fn i32(&mut self, v: i32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn i64(&mut self, v: i64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn finish(mut self) -> Vec<u8> {
        let n = self.0.len() as u32;
        self.0[..4].copy_from_slice(&n.to_le_bytes());
        self.0
    }
}

/// The `CreateImage` packet for a `width × height` image with `channels`.
pub fn create_image(name: &str, width: u32, height: u32, channels: &[&str]) -> Vec<u8> {
    let mut p = Packet::new(packet_type::CREATE_IMAGE);
    p.bool(true);
    p.str(name);
    p.i32(width as i32);
    p.i32(height as i32);
    p.i32(channels.len() as i32);
    for c in channels {
        p.str(c);
    }
    p.finish()
}

/// The `UpdateImage` (version 3) packet for the `w × h` rectangle at `(x, y)`; `data` holds
/// `channels.len()` interleaved floats per pixel, row-major.
pub fn update_image(
    name: &str,
    channels: &[&str],
    (x, y, w, h): (i32, i32, i32, i32),
    data: &[f32],
) -> Vec<u8> {
    let n = channels.len();
    let mut p = Packet::new(packet_type::UPDATE_IMAGE_V3);
    p.bool(false);
    p.str(name);
    p.i32(n as i32);
    for c in channels {
        p.str(c);
    }
    for v in [x, y, w, h] {
        p.i32(v);
    }
    for c in 0..n {
        p.i64(c as i64); // offset of channel c
    }
    for _ in 0..n {
        p.i64(n as i64); // stride: one pixel
    }
    p.0.reserve(data.len() * 4);
    for v in data {
        p.0.extend_from_slice(&v.to_le_bytes());
    }
    p.finish()
}

/// Splits `rect` into strips of whole rows holding at most [`MAX_FLOATS_PER_PACKET`] floats.
pub fn strips(rect: &PixelBounds) -> Vec<PixelBounds> {
    let per_row = (rect.width() as usize * CHANNELS.len()).max(1);
    let rows = (MAX_FLOATS_PER_PACKET / per_row).max(1) as i32;
    let mut out = Vec::new();
    let mut y = rect.y0;
    while y < rect.y1 {
        out.push(PixelBounds {
            y0: y,
            y1: (y + rows).min(rect.y1),
            ..*rect
        });
        y += rows;
    }
    out
}

/// Starts streaming `live` to the tev at `address` (HOST:PORT) on a new thread, under the
/// image name `name`. The thread ends after sending the final image (once
/// [`LiveImage::finish`] is called), or at the first network error, with a warning.
pub fn spawn(address: String, name: String, live: Arc<LiveImage>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        if let Err(e) = stream(&address, &name, &live) {
            eprintln!("warning: display server {address}: {e}; the render goes on without it");
            live.stop_tracking();
        }
    })
}

fn connect(address: &str) -> std::io::Result<TcpStream> {
    let mut last = std::io::Error::new(std::io::ErrorKind::NotFound, "no address");
    for a in address.to_socket_addrs()? {
        match TcpStream::connect_timeout(&a, Duration::from_secs(5)) {
            Ok(s) => return Ok(s),
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn stream(address: &str, name: &str, live: &LiveImage) -> std::io::Result<()> {
    let mut s = connect(address)?;
    s.set_write_timeout(Some(Duration::from_secs(10)))?;
    let _ = s.set_nodelay(true);
    let (w, h) = live.size();
    s.write_all(&create_image(name, w, h, &CHANNELS))?;
    let send = |s: &mut TcpStream, rects: &[(PixelBounds, Vec<f32>)]| -> std::io::Result<()> {
        for (r, data) in rects {
            let rect = (r.x0, r.y0, r.width() as i32, r.height() as i32);
            s.write_all(&update_image(name, &CHANNELS, rect, data))?;
        }
        Ok(())
    };
    loop {
        let (tiles, done) = live.wait_dirty(Duration::from_millis(500));
        let updates: Vec<_> = tiles
            .iter()
            .flat_map(strips)
            .map(|r| {
                let data = live.floats(&r);
                (r, data)
            })
            .collect();
        send(&mut s, &updates)?;
        if done {
            break;
        }
    }
    // The final image, everything, in strips.
    let whole = PixelBounds {
        x0: 0,
        x1: w as i32,
        y0: 0,
        y1: h as i32,
    };
    let updates: Vec<_> = strips(&whole)
        .into_iter()
        .map(|r| {
            let data = live.floats(&r);
            (r, data)
        })
        .collect();
    send(&mut s, &updates)?;
    s.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn create_image_packet_layout() {
        let p = create_image("a", 3, 2, &["R", "G"]);
        let mut want = vec![0u8; 4];
        want.extend_from_slice(&[4, 1, b'a', 0]);
        want.extend_from_slice(&3i32.to_le_bytes());
        want.extend_from_slice(&2i32.to_le_bytes());
        want.extend_from_slice(&2i32.to_le_bytes());
        want.extend_from_slice(b"R\0G\0");
        let n = want.len() as u32;
        want[..4].copy_from_slice(&n.to_le_bytes());
        assert_eq!(p, want);
    }

    #[test]
    fn update_image_packet_layout() {
        let p = update_image("im", &["R"], (1, 2, 2, 1), &[0.5, -1.0]);
        // 4 + 1 type + 1 focus + 3 name + 4 count + 2 channel + 16 rect + 8 + 8 + 8 data
        assert_eq!(p.len(), 55);
        assert_eq!(u32::from_le_bytes(p[..4].try_into().unwrap()), 55);
        assert_eq!(p[4], 6);
        assert_eq!(&p[6..9], b"im\0");
        assert_eq!(&p[13..15], b"R\0");
        assert_eq!(i32::from_le_bytes(p[15..19].try_into().unwrap()), 1);
        assert_eq!(i32::from_le_bytes(p[27..31].try_into().unwrap()), 1);
        assert_eq!(i64::from_le_bytes(p[31..39].try_into().unwrap()), 0);
        assert_eq!(i64::from_le_bytes(p[39..47].try_into().unwrap()), 1);
        assert_eq!(f32::from_le_bytes(p[47..51].try_into().unwrap()), 0.5);
        assert_eq!(f32::from_le_bytes(p[51..55].try_into().unwrap()), -1.0);
    }

    #[test]
    fn strips_cover_the_rectangle_within_the_packet_limit() {
        let r = PixelBounds {
            x0: 0,
            x1: 1000,
            y0: 0,
            y1: 777,
        };
        let s = strips(&r);
        assert_eq!(s.iter().map(|b| b.area()).sum::<u64>(), r.area());
        assert!(
            s.iter()
                .all(|b| b.area() as usize * 3 <= MAX_FLOATS_PER_PACKET)
        );
        assert_eq!(s.first().unwrap().y0, 0);
        assert_eq!(s.last().unwrap().y1, 777);
    }
}
