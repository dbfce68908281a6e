//! OpenEXR files of pictures (the `exr` crate): one layer of 32-bit float channels, ZIP
//! compressed (lossless, read by every EXR reader), written atomically.
//!
//! - A render has channels R, G, B: exitance per mm² per unit incident power, linear.
//! - A difference has one channel Y: signed luminance (R + G + B), same unit.
//!
//! Row 0 is the top of the picture (+y), column 0 its left (−x), as EXR stores them. The
//! metadata of [`super::Picture::meta`] become text attributes of the layer (`bssrdf:model`,
//! `bssrdf:material`, `bssrdf:photons`, `bssrdf:theta_deg`, `bssrdf:seed`, `bssrdf:extent_mm`,
//! …); characters outside Latin-1, which EXR text cannot hold, are written as `?`.

use super::{Frame, Picture, RenderError, META_PREFIX};
use ::exr::prelude::*;
use std::io::Cursor;
use std::path::Path;
// The exr prelude's `Result` is its own; ours is std's.
use std::result::Result;

/// Writes a render's RGB picture to `path`.
pub fn write_rgb(path: &Path, picture: &Picture) -> Result<(), RenderError> {
    let rgb = picture.rgb();
    let channels = ["R", "G", "B"]
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let samples: Vec<f32> = rgb.iter().skip(c).step_by(3).copied().collect();
            AnyChannel::new(*name, FlatSamples::F32(samples))
        })
        .collect();
    write(path, picture.frame(), picture.meta(), channels)
}

/// Writes a one-channel (Y) picture of `values` (row-major) to `path`.
pub fn write_luminance(
    path: &Path,
    frame: &Frame,
    values: &[f32],
    meta: &[(String, String)],
) -> Result<(), RenderError> {
    let channel = AnyChannel::new("Y", FlatSamples::F32(values.to_vec()));
    write(path, frame, meta, vec![channel])
}

fn write(
    path: &Path,
    frame: &Frame,
    meta: &[(String, String)],
    channels: Vec<AnyChannel<FlatSamples>>,
) -> Result<(), RenderError> {
    let fail = |message: String| RenderError::WriteExr {
        path: path.to_path_buf(),
        message,
    };
    let mut attributes = LayerAttributes::named("exitance");
    attributes.comments = Some(text(super::UNITS));
    for (key, value) in meta {
        attributes
            .other
            .insert(text(key), AttributeValue::Text(text(value)));
    }
    let layer = Layer::new(
        (frame.width(), frame.height()),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let mut bytes = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    crate::format::write_file_atomic(path, bytes.get_ref()).map_err(|e| fail(e.to_string()))
}

/// EXR text from a string, Latin-1 kept and anything else replaced by `?`.
fn text(s: &str) -> Text {
    let latin1: String = s
        .chars()
        .map(|c| if u32::from(c) < 256 { c } else { '?' })
        .collect();
    Text::new_or_none(latin1).unwrap_or_default()
}

/// What [`read()`] returns: the channels by name, the frame and the metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct ExrFile {
    /// (name, row-major samples as f32), in the file's (alphabetical) order.
    pub channels: Vec<(String, Vec<f32>)>,
    /// Width and height, pixels.
    pub size: (usize, usize),
    /// Every text attribute, (key, value).
    pub meta: Vec<(String, String)>,
}

/// Reads the first layer of any EXR file, every channel as f32.
pub fn read(path: &Path) -> Result<ExrFile, RenderError> {
    let fail = |message: String| RenderError::ReadExr {
        path: path.to_path_buf(),
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| fail(e.to_string()))?;
    let image = read_all_data_from_reader(Cursor::new(bytes));
    let image = image.map_err(|e| fail(e.to_string()))?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| fail("the file holds no layer".to_string()))?;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|ch| {
            (
                ch.name.to_string(),
                ch.sample_data.values_as_f32().collect(),
            )
        })
        .collect();
    let mut meta: Vec<(String, String)> = image
        .attributes
        .other
        .iter()
        .chain(&layer.attributes.other)
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            _ => None,
        })
        .collect();
    meta.sort();
    Ok(ExrFile {
        channels,
        size: (layer.size.width(), layer.size.height()),
        meta,
    })
}

fn read_all_data_from_reader(
    reader: Cursor<Vec<u8>>,
) -> ::exr::error::Result<Image<Layers<AnyChannels<FlatSamples>>>> {
    ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .non_parallel()
        .from_buffered(reader)
}

/// Reads a render written by [`write_rgb`]: channels R, G, B and the `bssrdf:extent_mm`
/// attribute are required.
pub fn read_picture(path: &Path) -> Result<Picture, RenderError> {
    let file = read(path)?;
    let missing = |what: String| RenderError::NotARender {
        path: path.to_path_buf(),
        what,
    };
    let channel = |name: &str| {
        file.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
            .ok_or_else(|| missing(format!("channel {name}")))
    };
    let (r, g, b) = (channel("R")?, channel("G")?, channel("B")?);
    let key = format!("{META_PREFIX}extent_mm");
    let extent = file
        .meta
        .iter()
        .find(|(k, _)| *k == key)
        .and_then(|(_, v)| v.parse::<f64>().ok())
        .filter(|e| e.is_finite() && *e > 0.0)
        .ok_or_else(|| missing(format!("positive number in attribute {key}")))?;
    let (width, height) = file.size;
    for (name, samples) in [("R", r), ("G", g), ("B", b)] {
        if samples.len() != width * height {
            return Err(missing(format!(
                "{}x{} samples in channel {name} (it has {})",
                width,
                height,
                samples.len()
            )));
        }
    }
    let rgb = (0..width * height)
        .flat_map(|i| [r[i], g[i], b[i]])
        .collect();
    Picture::new(Frame::new(width, height, extent), rgb, file.meta)
}
