//! A tiny raster canvas for the diagnostic PNGs: filled rectangles, axes with
//! labelled ticks, and text in an embedded 5x7 bitmap font (drawn here, scaled
//! by an integer factor). Everything is integer arithmetic, so the same input
//! always gives the same bytes.

/// Glyph cell: 5 columns, 7 rows above the baseline and 2 below for descenders.
const GLYPH_W: usize = 5;
const GLYPH_ROWS: usize = 9;
/// Rows above the baseline (cap height); what `text` treats as the line height.
pub const CAP_H: usize = 7;
/// Horizontal advance per character, in unscaled pixels (glyph plus one gap).
const ADVANCE: usize = GLYPH_W + 1;

/// One row per entry, top to bottom; bit 4 is the leftmost column.
#[rustfmt::skip]
fn glyph(c: char) -> [u8; GLYPH_ROWS] {
    match c {
        '0' => [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110, 0, 0],
        '1' => [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0, 0],
        '2' => [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111, 0, 0],
        '3' => [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110, 0, 0],
        '4' => [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010, 0, 0],
        '5' => [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110, 0, 0],
        '6' => [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110, 0, 0],
        '7' => [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0, 0],
        '8' => [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110, 0, 0],
        '9' => [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100, 0, 0],
        'A' => [0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001, 0, 0],
        'B' => [0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110, 0, 0],
        'C' => [0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110, 0, 0],
        'D' => [0b11110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b11110, 0, 0],
        'E' => [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111, 0, 0],
        'F' => [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000, 0, 0],
        'G' => [0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111, 0, 0],
        'H' => [0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001, 0, 0],
        'I' => [0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0, 0],
        'J' => [0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100, 0, 0],
        'K' => [0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001, 0, 0],
        'L' => [0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111, 0, 0],
        'M' => [0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001, 0, 0],
        'N' => [0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001, 0, 0],
        'O' => [0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110, 0, 0],
        'P' => [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000, 0, 0],
        'Q' => [0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101, 0, 0],
        'R' => [0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001, 0, 0],
        'S' => [0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110, 0, 0],
        'T' => [0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0, 0],
        'U' => [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110, 0, 0],
        'V' => [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0, 0],
        'W' => [0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010, 0, 0],
        'X' => [0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001, 0, 0],
        'Y' => [0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100, 0b00100, 0, 0],
        'Z' => [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111, 0, 0],
        'a' => [0, 0, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111, 0, 0],
        'b' => [0b10000, 0b10000, 0b11110, 0b10001, 0b10001, 0b10001, 0b11110, 0, 0],
        'c' => [0, 0, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110, 0, 0],
        'd' => [0b00001, 0b00001, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0, 0],
        'e' => [0, 0, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110, 0, 0],
        'f' => [0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000, 0, 0],
        'g' => [0, 0, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110],
        'h' => [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001, 0, 0],
        'i' => [0b00100, 0, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110, 0, 0],
        'j' => [0b00010, 0, 0b00110, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100],
        'k' => [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0, 0],
        'l' => [0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0, 0],
        'm' => [0, 0, 0b11010, 0b10101, 0b10101, 0b10101, 0b10101, 0, 0],
        'n' => [0, 0, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001, 0, 0],
        'o' => [0, 0, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110, 0, 0],
        'p' => [0, 0, 0b11110, 0b10001, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000],
        'q' => [0, 0, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b00001],
        'r' => [0, 0, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000, 0, 0],
        's' => [0, 0, 0b01111, 0b10000, 0b01110, 0b00001, 0b11110, 0, 0],
        't' => [0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110, 0, 0],
        'u' => [0, 0, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101, 0, 0],
        'v' => [0, 0, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0, 0],
        'w' => [0, 0, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010, 0, 0],
        'x' => [0, 0, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0, 0],
        'y' => [0, 0, 0b10001, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110],
        'z' => [0, 0, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111, 0, 0],
        ' ' => [0; GLYPH_ROWS],
        ',' => [0, 0, 0, 0, 0, 0b01100, 0b01100, 0b00100, 0b01000],
        '.' => [0, 0, 0, 0, 0, 0b01100, 0b01100, 0, 0],
        ':' => [0, 0b01100, 0b01100, 0, 0b01100, 0b01100, 0, 0, 0],
        '-' => [0, 0, 0, 0b01110, 0, 0, 0, 0, 0],
        '+' => [0, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0, 0, 0],
        '/' => [0b00001, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b10000, 0, 0],
        '(' => [0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010, 0, 0],
        ')' => [0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000, 0, 0],
        // Anything else shows as a hollow box rather than vanishing.
        _ => [0b11111, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b11111, 0, 0],
    }
}

/// Width in pixels of `s` drawn at `scale` (no trailing gap).
pub fn text_width(s: &str, scale: usize) -> usize {
    (s.chars().count() * ADVANCE).saturating_sub(1) * scale
}

/// `1234567` -> `"1,234,567"`.
pub fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The smallest step of the form 1, 2 or 5 times a power of ten that splits
/// `0..=max` into at most `max_intervals` intervals.
pub fn nice_step(max: usize, max_intervals: usize) -> usize {
    let mut magnitude = 1usize;
    loop {
        for m in [1, 2, 5] {
            let step = m * magnitude;
            if max / step <= max_intervals {
                return step;
            }
        }
        magnitude *= 10;
    }
}

/// A plot area: bars and data live in `x0..x0 + w` and in the rows
/// `y_base - h..y_base` (row `y_base` is the x axis).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub x0: usize,
    pub y_base: usize,
    pub w: usize,
    pub h: usize,
}

/// An RGB image, row-major, three bytes per pixel.
pub struct Canvas {
    pub width: usize,
    pub height: usize,
    background: [u8; 3],
    px: Vec<u8>,
}

/// Text, ticks and axis lines.
pub const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [225, 225, 225];

impl Canvas {
    /// A `width` x `height` canvas filled with `background`.
    pub fn new(width: usize, height: usize, background: [u8; 3]) -> Self {
        let mut px = Vec::with_capacity(width * height * 3);
        for _ in 0..width * height {
            px.extend_from_slice(&background);
        }
        Canvas {
            width,
            height,
            background,
            px,
        }
    }

    fn set(&mut self, x: usize, y: usize, color: [u8; 3]) {
        if x < self.width && y < self.height {
            let i = (y * self.width + x) * 3;
            self.px[i..i + 3].copy_from_slice(&color);
        }
    }

    fn is_background(&self, x: usize, y: usize) -> bool {
        let i = (y * self.width + x) * 3;
        self.px[i..i + 3] == self.background
    }

    /// Fills `x..x + w` by `y..y + h`, clipped to the canvas.
    pub fn fill_rect(&mut self, x: usize, y: usize, w: usize, h: usize, color: [u8; 3]) {
        for yy in y..(y + h).min(self.height) {
            for xx in x..(x + w).min(self.width) {
                self.set(xx, yy, color);
            }
        }
    }

    /// Draws `s` with its top-left corner at (x, y); `y` is the top of the capitals.
    pub fn text(&mut self, x: usize, y: usize, s: &str, scale: usize, color: [u8; 3]) {
        for (i, c) in s.chars().enumerate() {
            let gx = x + i * ADVANCE * scale;
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH_W {
                    if bits & (1 << (GLYPH_W - 1 - col)) != 0 {
                        self.fill_rect(gx + col * scale, y + row * scale, scale, scale, color);
                    }
                }
            }
        }
    }

    /// Axis lines, tick marks and tick labels for `frame`, plus light horizontal
    /// grid lines at the count ticks. The x axis spans values `0..x_span`
    /// (`x_span` at the right edge) with ticks every `x_step`; the y axis spans
    /// `0..=y_top` with ticks every `y_step`. Call after drawing the data: grid
    /// lines only recolour background pixels, so they stay behind the bars.
    pub fn axes(
        &mut self,
        frame: Frame,
        x_span: usize,
        x_step: usize,
        y_top: usize,
        y_step: usize,
        scale: usize,
    ) {
        let Frame { x0, y_base, w, h } = frame;
        let tick = 3 * scale;
        let gap = 3 * scale;
        let axis_x = x0.saturating_sub(2);
        // y ticks, labels and grid lines.
        let mut v = 0;
        while v <= y_top {
            let y = y_base - v * h / y_top.max(1);
            if v > 0 {
                for x in x0..x0 + w {
                    if self.is_background(x, y) {
                        self.set(x, y, GRID);
                    }
                }
            }
            self.fill_rect(axis_x.saturating_sub(tick), y, tick, 1, BLACK);
            let label = v.to_string();
            let lx = axis_x.saturating_sub(tick + gap + text_width(&label, scale));
            self.text(
                lx,
                y.saturating_sub(CAP_H * scale / 2),
                &label,
                scale,
                BLACK,
            );
            v += y_step.max(1);
        }
        // x ticks and labels, centred under the tick.
        let mut v = 0;
        while v < x_span {
            let x = x0 + v * w / x_span;
            self.fill_rect(x, y_base + 1, 1, tick, BLACK);
            let label = v.to_string();
            let lx = x.saturating_sub(text_width(&label, scale) / 2);
            self.text(lx, y_base + 1 + tick + gap, &label, scale, BLACK);
            v += x_step.max(1);
        }
        // The axis lines themselves.
        self.fill_rect(axis_x, y_base - h, 1, h + 1, BLACK);
        self.fill_rect(axis_x, y_base, x0 + w - axis_x, 1, BLACK);
    }

    /// The image as an 8-bit RGB PNG (no timestamps or other varying chunks).
    pub fn to_png(&self) -> Result<Vec<u8>, png::EncodingError> {
        let mut bytes = Vec::new();
        let mut enc = png::Encoder::new(&mut bytes, self.width as u32, self.height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()?.write_image_data(&self.px)?;
        Ok(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_and_numbers() {
        assert_eq!(nice_step(4096, 4), 1000);
        assert_eq!(nice_step(8000, 4), 2000);
        assert_eq!(nice_step(900, 4), 200);
        assert_eq!(nice_step(1, 4), 1);
        assert_eq!(nice_step(0, 4), 1);
        assert_eq!(thousands(5769), "5,769");
        assert_eq!(thousands(259), "259");
        assert_eq!(thousands(1_234_567), "1,234,567");
        assert_eq!(text_width("ab", 2), 22);
        assert_eq!(text_width("", 2), 0);
    }
}
