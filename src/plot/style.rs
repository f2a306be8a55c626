//! The look of every figure and how it reaches the disk: the embedded font, the palette, the
//! figure and text sizes, tick-label formatters, and rendering a bitmap to exactly the path the
//! caller gave (PNG by the `png` crate, whatever the path's extension).

use std::error::Error as StdError;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::error::{Error, Result};

/// Font family name under which the embedded DejaVu Sans font is registered.
const FONT: &str = "sans-serif";

/// The embedded font file.
static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Root drawing area of one figure.
pub(super) type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Result of the drawing closures (any `plotters` error).
pub(super) type DrawResult = std::result::Result<(), Box<dyn StdError>>;

/// Distinct colours (the "tab10" palette).
pub(super) const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colours of the categories past the palette's ten (a map's dry whirl and dry whip): dark
/// blue and dark red, apart from every colour of [`PALETTE`].
pub(super) const PALETTE_MORE: [RGBColor; 2] = [RGBColor(0, 0, 110), RGBColor(110, 0, 0)];

/// The colour of category `k`: [`PALETTE`], then [`PALETTE_MORE`], then round again.
pub(super) fn category_colour(k: usize) -> RGBColor {
    let k = k % (PALETTE.len() + PALETTE_MORE.len());
    PALETTE
        .get(k)
        .copied()
        .unwrap_or_else(|| PALETTE_MORE[k - PALETTE.len()])
}

/// Width of the ordinary (non-grid) figures in pixels.
pub(super) const FIG_W: u32 = 1200;
/// Height of the ordinary (non-grid) figures in pixels.
pub(super) const FIG_H: u32 = 900;
/// Font size of figure titles.
pub(super) const TITLE_SIZE: f64 = 30.0;
/// Font size of tick labels.
pub(super) const TICK_SIZE: f64 = 17.0;
/// Font size of axis descriptions.
pub(super) const DESC_SIZE: f64 = 20.0;

/// Registers the embedded font once; an error message if it cannot be parsed.
fn ensure_font() -> std::result::Result<(), &'static str> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err("the embedded font DejaVuSans.ttf could not be loaded")
    }
}

/// Text style of the embedded font at `size` pixels, black.
pub(super) fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// Renders a figure of `size` pixels with `draw` and writes it as PNG to `path`, whatever its
/// extension (a caller's temporary name included).
///
/// The figure is drawn into an RGB buffer and encoded by the `png` crate with the settings
/// plotters' `image` encoder used (fast compression, adaptive filtering), so the files are the
/// same; the `image` crate and its decoders stay out of the build. On failure no file is left
/// behind.
pub(super) fn render<F>(path: &Path, size: (u32, u32), draw: F) -> Result<()>
where
    F: FnOnce(&Root<'_>) -> DrawResult,
{
    ensure_font().map_err(|m| Error::output(path, m))?;
    let size = (size.0.clamp(200, 20_000), size.1.clamp(200, 20_000));
    let mut pixels = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        root.fill(&WHITE)
            .map_err(|e| Error::output(path, format!("cannot draw plot: {e}")))?;
        draw(&root).map_err(|e| Error::output(path, format!("cannot draw plot: {e}")))?;
        root.present()
            .map_err(|e| Error::output(path, format!("cannot draw plot: {e}")))?;
    }
    write_png(path, size, &pixels).map_err(|e| {
        let _ = std::fs::remove_file(path);
        Error::output(path, format!("cannot write PNG: {e}"))
    })
}

/// Encodes the 8-bit RGB `pixels` of a `size` image as PNG into `path`.
fn write_png(path: &Path, size: (u32, u32), pixels: &[u8]) -> std::io::Result<()> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, size.0, size.1);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::FilterType::Sub);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(pixels)?;
    writer.finish()?;
    Ok(())
}

/// The embedded font at `size`, shrunk (down to 10 px) so that `text` fits the width of `area`
/// with a 10-pixel margin on each side.
pub(super) fn fitting_font<C: CoordTranslate>(
    area: &DrawingArea<BitMapBackend<'_>, C>,
    text: &str,
    size: f64,
) -> std::result::Result<TextStyle<'static>, Box<dyn StdError>> {
    let (w, _) = area.dim_in_pixel();
    let avail = f64::from(w.saturating_sub(20).max(1));
    let (tw, _) = area.estimate_text_size(text, &font(size))?;
    if f64::from(tw) <= avail {
        return Ok(font(size));
    }
    Ok(font((size * avail / f64::from(tw)).floor().max(10.0)))
}

/// Tick-label formatter for a linear axis over `lo..hi` with about `n` labels: fixed decimals
/// matching the tick step, scientific notation for very large or very small magnitudes.
pub(super) fn tick_formatter(lo: f64, hi: f64, n: usize) -> impl Fn(&f64) -> String {
    let span = (hi - lo).abs();
    let raw = if span > 0.0 {
        span / n.max(1) as f64
    } else {
        1.0
    };
    let p = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * p);
    let mag = lo.abs().max(hi.abs());
    let sci = !(1e-3..1e5).contains(&mag);
    let decimals = (-step.log10().floor()).clamp(0.0, 12.0) as usize;
    let sci_decimals = (mag.log10().floor() - step.log10().floor()).clamp(0.0, 6.0) as usize;
    // plotters may place ticks on a finer step than the one assumed from `n` (ticks 0.5 apart
    // where `step` is 1): a value not exact at the step's decimals takes up to two more, so
    // that 2.5 is not printed "2".
    let more = move |v: f64, d: usize, scale: f64| {
        (0..=2)
            .find(|k| {
                let f = 10f64.powi((d + k) as i32) / scale;
                ((v * f).round() - v * f).abs() <= 1e-6 * step * f
            })
            .map_or(d + 2, |k| d + k)
    };
    move |v: &f64| {
        let v = if v.abs() < step * 1e-6 { 0.0 } else { *v };
        if v == 0.0 {
            "0".to_string()
        } else if sci {
            let scale = 10f64.powf(v.abs().log10().floor());
            let d = more(v, sci_decimals, scale);
            trim_mantissa(&format!("{v:.d$e}"))
        } else {
            let d = more(v, decimals, 1.0);
            format!("{v:.d$}")
        }
    }
}

/// Removes trailing zeros of the mantissa of a number in `{:e}` format (`1.50e-9` → `1.5e-9`).
fn trim_mantissa(s: &str) -> String {
    match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            let m = m.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{e}")
        }
        _ => s.to_string(),
    }
}

/// Tick-label formatter of a logarithmic axis over `lo..hi`: plain decimals if the whole axis
/// lies within 0.01..10⁴, otherwise powers of ten (`10⁻⁵`, `2×10⁻⁵`) throughout.
pub(super) fn log_formatter(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let plain = lo >= 0.00999 && hi <= 10_001.0;
    move |v: &f64| log_label(*v, plain)
}

/// Tick label of a logarithmic axis: plain decimals if `plain`, otherwise `10⁻⁵` or `2×10⁻⁵`.
fn log_label(v: f64, plain: bool) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    let (m, e) = if m >= 9.9995 { (1.0, e + 1.0) } else { (m, e) };
    if plain {
        let d = (-e).max(0.0) as usize + usize::from((m - m.round()).abs() > 1e-6);
        return format!("{v:.d$}");
    }
    let exp = superscript(e as i64);
    if (m - 1.0).abs() < 1e-6 {
        format!("10{exp}")
    } else if (m - m.round()).abs() < 1e-6 {
        format!("{}×10{exp}", m.round())
    } else {
        format!("{m:.1}×10{exp}")
    }
}

/// An integer in Unicode superscript digits.
fn superscript(k: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// A number with about three significant digits.
pub(super) fn fmt_sig(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.2e}")
    } else {
        let d = (2.0 - a.log10().floor()).clamp(0.0, 6.0) as usize;
        format!("{v:.d$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers() {
        let f = tick_formatter(0.0, 1.0, 10);
        assert_eq!(f(&0.3), "0.3");
        assert_eq!(f(&-1e-17), "0");
        let f = tick_formatter(0.0, 2e-6, 10);
        assert_eq!(f(&1e-6), "1e-6");
        assert_eq!(f(&1.5e-6), "1.5e-6");
        // Ticks finer than the assumed step keep their digits.
        let f = tick_formatter(0.4, 3.1, 5);
        assert_eq!(
            (f(&2.5), f(&3.0), f(&1.25)),
            ("2.5".into(), "3".into(), "1.25".into())
        );
        let f = tick_formatter(0.0, 2e-6, 5);
        assert_eq!((f(&5e-7), f(&1.25e-6)), ("5e-7".into(), "1.25e-6".into()));
        assert_eq!(trim_mantissa("5.00e-10"), "5e-10");
        assert_eq!(log_label(1e-5, false), "10⁻⁵");
        assert_eq!(log_label(0.01, true), "0.01");
        assert_eq!(log_label(0.01, false), "10⁻²");
        assert_eq!(log_label(100.0, true), "100");
        assert_eq!(log_label(2e6, false), "2×10⁶");
    }
}
