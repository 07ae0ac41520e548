//! OIDN's U-Net (`UNetFilter::addUNet`, the "base" model that quality "high" uses for the
//! `rt` filter's HDR networks), run on one tile.
//!
//! Levels 0..4 halve the resolution; `conv` is a 3×3 convolution + ReLU, `pool` 2×2 max
//! pooling, `up` nearest 2× upsampling, `[a | b]` channel concatenation (a's channels first):
//!
//! ```text
//! enc_conv0(input)            enc_conv1 → pool1      enc_conv2 → pool2
//! enc_conv3 → pool3           enc_conv4 → pool4      enc_conv5a, enc_conv5b → up
//! dec_conv4a([up | pool3]), dec_conv4b → up          dec_conv3a([up | pool2]), dec_conv3b → up
//! dec_conv2a([up | pool1]), dec_conv2b → up          dec_conv1a([up | input]), dec_conv1b
//! dec_conv0 (3 channels, ReLU)
//! ```
//!
//! Each concatenation is one tensor whose second half is written when the skip is made; the
//! tensors live in a [`Workspace`] reused from tile to tile and layer to layer.

use crate::conv::Conv;
use crate::tensor::{Tensor, pool_into, upsample_into};
use crate::tza;

/// The trained layers of one network.
#[derive(Clone, Debug)]
pub struct UNet {
    /// Channels of the input (3 colour, + 3 albedo, + 3 normal).
    pub input_channels: usize,
    enc0: Conv,
    enc1: Conv,
    enc2: Conv,
    enc3: Conv,
    enc4: Conv,
    enc5a: Conv,
    enc5b: Conv,
    dec4a: Conv,
    dec4b: Conv,
    dec3a: Conv,
    dec3b: Conv,
    dec2a: Conv,
    dec2b: Conv,
    dec1a: Conv,
    dec1b: Conv,
    dec0: Conv,
}

/// Why a network could not be built from a blob.
#[derive(Debug, thiserror::Error)]
pub enum NetError {
    /// The blob is not a readable TZA file.
    #[error(transparent)]
    Tza(#[from] tza::TzaError),
    /// A layer is missing or has the wrong shape.
    #[error("weights blob: layer {0}: {1}")]
    Layer(String, String),
}

impl UNet {
    /// The network stored in a TZA blob.
    pub fn from_tza(blob: &[u8]) -> Result<Self, NetError> {
        let t = tza::parse(blob)?;
        let layer = |name: &str, cin: Option<usize>| -> Result<Conv, NetError> {
            let err = |m: &str| NetError::Layer(name.to_string(), m.to_string());
            let w = t
                .get(&format!("{name}.weight"))
                .ok_or_else(|| err("no weight"))?;
            let b = t
                .get(&format!("{name}.bias"))
                .ok_or_else(|| err("no bias"))?;
            let [o, i, 3, 3] = w.dims[..] else {
                return Err(err("weight not o×i×3×3"));
            };
            if b.dims != [o] || cin.is_some_and(|c| c != i) {
                return Err(err(&format!("shape {:?} / bias {:?}", w.dims, b.dims)));
            }
            Ok(Conv::new(o, i, &w.data, &b.data))
        };
        let enc0 = layer("enc_conv0", None)?;
        let input_channels = enc0.cin;
        let enc1 = layer("enc_conv1", Some(enc0.cout))?;
        let enc2 = layer("enc_conv2", Some(enc1.cout))?;
        let enc3 = layer("enc_conv3", Some(enc2.cout))?;
        let enc4 = layer("enc_conv4", Some(enc3.cout))?;
        let enc5a = layer("enc_conv5a", Some(enc4.cout))?;
        let enc5b = layer("enc_conv5b", Some(enc5a.cout))?;
        let dec4a = layer("dec_conv4a", Some(enc5b.cout + enc3.cout))?;
        let dec4b = layer("dec_conv4b", Some(dec4a.cout))?;
        let dec3a = layer("dec_conv3a", Some(dec4b.cout + enc2.cout))?;
        let dec3b = layer("dec_conv3b", Some(dec3a.cout))?;
        let dec2a = layer("dec_conv2a", Some(dec3b.cout + enc1.cout))?;
        let dec2b = layer("dec_conv2b", Some(dec2a.cout))?;
        let dec1a = layer("dec_conv1a", Some(dec2b.cout + input_channels))?;
        let dec1b = layer("dec_conv1b", Some(dec1a.cout))?;
        let dec0 = layer("dec_conv0", Some(dec1b.cout))?;
        if dec0.cout != 3 {
            return Err(NetError::Layer(
                "dec_conv0".into(),
                "not 3 output channels".into(),
            ));
        }
        Ok(Self {
            input_channels,
            enc0,
            enc1,
            enc2,
            enc3,
            enc4,
            enc5a,
            enc5b,
            dec4a,
            dec4b,
            dec3a,
            dec3b,
            dec2a,
            dec2b,
            dec1a,
            dec1b,
            dec0,
        })
    }

    /// The channels before the input's in the level-0 concatenation: the input tensor handed
    /// to [`UNet::run`] has `skip0_offset() + input_channels` channels, the input in the last
    /// ones (the first ones are filled by the decoder).
    pub fn skip0_offset(&self) -> usize {
        self.dec2b.cout
    }

    /// The buffers to run the network on `h`×`w` tiles ([`UNet::run`]), made once per image
    /// and reused for each tile.
    pub fn workspace(&self, h: usize, w: usize) -> Workspace {
        assert!(
            h.is_multiple_of(16) && w.is_multiple_of(16),
            "tile {w}x{h} not a multiple of 16"
        );
        let full = |c: usize| Tensor::zeros(c, h, w);
        Workspace {
            x0: full(self.skip0_offset() + self.input_channels),
            x1: Tensor::zeros(self.dec3b.cout + self.enc1.cout, h / 2, w / 2),
            x2: Tensor::zeros(self.dec4b.cout + self.enc2.cout, h / 4, w / 4),
            x3: Tensor::zeros(self.enc5b.cout + self.enc3.cout, h / 8, w / 8),
            p4: Tensor::zeros(self.enc4.cout, h / 16, w / 16),
            // the full-resolution layers each buffer receives (the lower levels' are smaller)
            a: full(self.enc0.cout.max(self.dec1a.cout).max(self.dec0.cout)),
            b: full(self.enc1.cout.max(self.dec1b.cout)),
        }
    }

    /// Runs the network on the workspace's input, `ws.x0`'s channels `skip0_offset()..` (the
    /// caller fills them; the channels before are the decoder's); returns the 3 output
    /// channels. The layers' outputs alternate between the buffers `a` and `b`.
    pub fn run<'w>(&self, ws: &'w mut Workspace) -> &'w Tensor {
        let off0 = self.skip0_offset();
        let Workspace {
            x0,
            x1,
            x2,
            x3,
            p4,
            a,
            b,
        } = ws;
        assert_eq!(x0.c, off0 + self.input_channels);

        self.enc0.run_into(x0, off0, a);
        self.enc1.run_into(a, 0, b);
        pool_into(b, x1, self.dec3b.cout);
        self.enc2.run_into(x1, self.dec3b.cout, a);
        pool_into(a, x2, self.dec4b.cout);
        self.enc3.run_into(x2, self.dec4b.cout, a);
        pool_into(a, x3, self.enc5b.cout);
        self.enc4.run_into(x3, self.enc5b.cout, a);
        pool_into(a, p4, 0);

        self.enc5a.run_into(p4, 0, a);
        self.enc5b.run_into(a, 0, b);
        upsample_into(b, x3);
        self.dec4a.run_into(x3, 0, a);
        self.dec4b.run_into(a, 0, b);
        upsample_into(b, x2);
        self.dec3a.run_into(x2, 0, a);
        self.dec3b.run_into(a, 0, b);
        upsample_into(b, x1);
        self.dec2a.run_into(x1, 0, a);
        self.dec2b.run_into(a, 0, b);
        upsample_into(b, x0);
        self.dec1a.run_into(x0, 0, a);
        self.dec1b.run_into(a, 0, b);
        self.dec0.run_into(b, 0, a);
        a
    }
}

/// The activations of one tile size: the input with the level-0 concatenation around it
/// (`x0`), the concatenations of levels 1..3 (`[upsampled decoder | pooled encoder]`), the
/// last pooling (`p4`), and two buffers the layers' outputs alternate between. About
/// 860 bytes per tile pixel for OIDN's networks (73 + 64 + 32 full-resolution channels and
/// the lower levels' 45 per pixel, 4 bytes each).
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Level 0: `[upsampled decoder | input]`.
    pub x0: Tensor,
    x1: Tensor,
    x2: Tensor,
    x3: Tensor,
    p4: Tensor,
    a: Tensor,
    b: Tensor,
}
