//! Raster cells in SVG without the `image` crate (issue 14, first-build time).
//!
//! plotters' SVG backend embeds a bitmap (`blit_bitmap`: the space–time cells, the colour bar)
//! as one `<image>` only with its `bitmap_encoder` feature, which compiles the whole `image`
//! crate (JPEG, BMP, … codecs; about 35 s of a cold build) to encode one PNG; without it, every
//! pixel becomes a `<rect>`. [`SvgImages`] wraps the SVG backend instead: each bitmap is encoded
//! with the `png` crate (already used for the PNG output), and a placeholder rectangle of a
//! reserved colour and opacity ([`PLACEHOLDER`]) is drawn in its place, so it keeps its position
//! in the drawing order; [`embed`] then replaces the k-th placeholder by the k-th image as a
//! base64 `data:image/png` URI. Everything else is delegated unchanged.

use plotters::prelude::SVGBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};
use std::cell::RefCell;
use std::rc::Rc;

/// The placeholder's fill colour and opacity (never used by a figure).
pub const PLACEHOLDER: BackendColor = BackendColor {
    alpha: 0.012_345,
    rgb: (1, 2, 3),
};

/// The text plotters writes for [`PLACEHOLDER`]'s opacity and fill.
const MARK: &str = r##"opacity="0.012345" fill="#010203""##;

/// An embedded bitmap: position, size and PNG bytes.
pub type Image = ((i32, i32), (u32, u32), Vec<u8>);

/// The SVG backend with bitmaps collected into `images` (see the module docs).
pub struct SvgImages<'a> {
    inner: SVGBackend<'a>,
    images: Rc<RefCell<Vec<Image>>>,
}

impl<'a> SvgImages<'a> {
    /// Wraps `inner`; bitmaps go to `images`.
    pub fn new(inner: SVGBackend<'a>, images: Rc<RefCell<Vec<Image>>>) -> Self {
        Self { inner, images }
    }
}

type Res = Result<(), DrawingErrorKind<std::io::Error>>;

impl DrawingBackend for SvgImages<'_> {
    type ErrorType = std::io::Error;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Res {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Res {
        self.inner.present()
    }
    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Res {
        self.inner.draw_pixel(p, c)
    }
    fn draw_line<S: BackendStyle>(&mut self, a: BackendCoord, b: BackendCoord, s: &S) -> Res {
        self.inner.draw_line(a, b, s)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
        fill: bool,
    ) -> Res {
        self.inner.draw_rect(a, b, s, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        s: &S,
    ) -> Res {
        self.inner.draw_path(path, s)
    }
    fn draw_circle<S: BackendStyle>(&mut self, c: BackendCoord, r: u32, s: &S, fill: bool) -> Res {
        self.inner.draw_circle(c, r, s, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        s: &S,
    ) -> Res {
        self.inner.fill_polygon(vert, s)
    }
    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, s: &T, p: BackendCoord) -> Res {
        self.inner.draw_text(text, s, p)
    }
    fn estimate_text_size<T: BackendTextStyle>(
        &self,
        text: &str,
        s: &T,
    ) -> Result<(u32, u32), DrawingErrorKind<std::io::Error>> {
        self.inner.estimate_text_size(text, s)
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, (w, h): (u32, u32), src: &[u8]) -> Res {
        let png = super::encode_png(src, (w, h))
            .map_err(|e| DrawingErrorKind::DrawingError(std::io::Error::other(e.to_string())))?;
        self.images.borrow_mut().push((pos, (w, h), png));
        let end = (pos.0 + w as i32, pos.1 + h as i32);
        self.inner.draw_rect(pos, end, &PLACEHOLDER, true)
    }
}

/// Why the raster images could not be embedded in the SVG text.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EmbedError {
    /// A placeholder colour outside a `<rect>` element.
    #[error("placeholder outside a <rect>")]
    OutsideRect,
    /// A placeholder `<rect>` without its end.
    #[error("unterminated placeholder")]
    Unterminated,
    /// More placeholders than images.
    #[error("more placeholders than images")]
    TooFewImages,
    /// Fewer placeholders than images.
    #[error("{images} images but {placeholders} placeholders")]
    Count {
        /// Images drawn.
        images: usize,
        /// Placeholders found.
        placeholders: usize,
    },
}

/// Replaces the placeholders of `svg` by `images`, in order; an error if the counts differ.
pub fn embed(svg: &str, images: &[Image]) -> Result<String, EmbedError> {
    let mut out =
        String::with_capacity(svg.len() + images.iter().map(|i| i.2.len() * 2).sum::<usize>());
    let mut rest = svg;
    let mut k = 0;
    while let Some(m) = rest.find(MARK) {
        let start = rest[..m].rfind("<rect").ok_or(EmbedError::OutsideRect)?;
        let end = m + rest[m..].find("/>").ok_or(EmbedError::Unterminated)? + 2;
        let ((x, y), (w, h), png) = images.get(k).ok_or(EmbedError::TooFewImages)?;
        out.push_str(&rest[..start]);
        out.push_str(&format!(
            r#"<image x="{x}" y="{y}" width="{w}" height="{h}" preserveAspectRatio="none" href="data:image/png;base64,{}"/>"#,
            base64(png)
        ));
        rest = &rest[end..];
        k += 1;
    }
    if k != images.len() {
        return Err(EmbedError::Count {
            images: images.len(),
            placeholders: k,
        });
    }
    out.push_str(rest);
    Ok(out)
}

/// Standard base64 (RFC 4648, with padding).
pub fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(data.len().div_ceil(3) * 4);
    for c in data.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for (i, shift) in [18, 12, 6, 0].iter().enumerate() {
            if i <= c.len() {
                s.push(A[(n >> shift & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_rfc4648_vectors() {
        let v = [
            "", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy",
        ];
        for (k, want) in v.iter().enumerate() {
            assert_eq!(base64(&b"foobar"[..k]), *want);
        }
    }

    #[test]
    fn placeholders_become_images_in_order() {
        let svg = format!(
            "<svg><rect x=\"1\" {MARK} stroke=\"none\"/><line/><rect x=\"2\" {MARK}/></svg>"
        );
        let imgs = vec![((1, 2), (3, 4), vec![0u8]), ((5, 6), (7, 8), vec![1u8])];
        let s = embed(&svg, &imgs).unwrap();
        assert_eq!(
            s,
            "<svg><image x=\"1\" y=\"2\" width=\"3\" height=\"4\" preserveAspectRatio=\"none\" \
             href=\"data:image/png;base64,AA==\"/><line/><image x=\"5\" y=\"6\" width=\"7\" \
             height=\"8\" preserveAspectRatio=\"none\" href=\"data:image/png;base64,AQ==\"/></svg>"
        );
        assert!(embed(&svg, &imgs[..1]).is_err());
    }
}
