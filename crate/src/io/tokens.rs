//! A byte-level tokenizer for the keyword-and-brace text formats (ASE, MD5).
//!
//! Tokens are separated by ASCII whitespace; a `"` starts a quoted token that ends at the next
//! `"` or at the end of the line (the quotes are not part of it); each byte of `punct` is a
//! token of its own; with `comments`, `//` starts a comment that runs to the end of the line.
//! Bytes are not decoded, so names in any encoding pass through; numbers must be ASCII.

use std::str::FromStr;

use super::{Format, Location, ReadError, malformed};

/// One token and the 1-based line it is on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    pub(crate) text: &'a [u8],
    pub(crate) line: usize,
}

impl Token<'_> {
    pub(crate) fn is(&self, s: &str) -> bool {
        self.text == s.as_bytes()
    }

    pub(crate) fn loc(&self) -> Location {
        Location::Line(self.line)
    }

    /// The token as text for messages (at most 40 characters, invalid UTF-8 replaced).
    pub(crate) fn show(&self) -> String {
        let s = String::from_utf8_lossy(self.text);
        match s.char_indices().nth(40) {
            Some((i, _)) => format!("{}...", &s[..i]),
            None => s.into_owned(),
        }
    }
}

pub(crate) struct Tokens<'a> {
    format: Format,
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    punct: &'static [u8],
    comments: bool,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(
        format: Format,
        bytes: &'a [u8],
        punct: &'static [u8],
        comments: bool,
    ) -> Self {
        Tokens {
            format,
            bytes,
            pos: 0,
            line: 1,
            punct,
            comments,
        }
    }

    /// Bytes not yet read.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next token, or `None` at the end of the input.
    pub(crate) fn next(&mut self) -> Option<Token<'a>> {
        let b = self.bytes;
        loop {
            while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
                if b[self.pos] == b'\n' {
                    self.line += 1;
                }
                self.pos += 1;
            }
            if self.comments && b[self.pos..].starts_with(b"//") {
                while self.pos < b.len() && b[self.pos] != b'\n' {
                    self.pos += 1;
                }
                continue;
            }
            break;
        }
        if self.pos >= b.len() {
            return None;
        }
        let line = self.line;
        let start = self.pos;
        if b[start] == b'"' {
            let body = start + 1;
            let end = b[body..]
                .iter()
                .position(|&c| c == b'"' || c == b'\n')
                .map_or(b.len(), |i| body + i);
            // Past the closing quote; a line end is left for the whitespace loop to count.
            self.pos = if end < b.len() && b[end] == b'"' {
                end + 1
            } else {
                end
            };
            return Some(Token {
                text: &b[body..end],
                line,
            });
        }
        if self.punct.contains(&b[start]) {
            self.pos += 1;
            return Some(Token {
                text: &b[start..start + 1],
                line,
            });
        }
        while self.pos < b.len()
            && !b[self.pos].is_ascii_whitespace()
            && b[self.pos] != b'"'
            && !self.punct.contains(&b[self.pos])
        {
            self.pos += 1;
        }
        Some(Token {
            text: &b[start..self.pos],
            line,
        })
    }

    /// The line of the last token read.
    pub(crate) fn loc_here(&self) -> Location {
        Location::Line(self.line)
    }

    /// The error for input that ends too early.
    pub(crate) fn eof(&self) -> ReadError {
        ReadError::Truncated {
            format: self.format,
            offset: self.bytes.len() as u64,
            expected: 1,
        }
    }

    /// The next token; `Truncated` at the end of the input.
    pub(crate) fn expect_any(&mut self) -> Result<Token<'a>, ReadError> {
        self.next().ok_or_else(|| self.eof())
    }

    /// The next token, which must be `s`.
    pub(crate) fn expect(&mut self, s: &str) -> Result<Token<'a>, ReadError> {
        let t = self.expect_any()?;
        if !t.is(s) {
            return Err(malformed(
                self.format,
                t.loc(),
                format!("`{}` where `{s}` was expected", t.show()),
            ));
        }
        Ok(t)
    }

    /// The next token parsed as a `T`; `what` names it in the error.
    pub(crate) fn number<T: FromStr>(&mut self, what: &str) -> Result<T, ReadError> {
        let t = self.expect_any()?;
        parse(self.format, &t, what)
    }

    /// The next token as an `f64` that is finite also as an `f32` (`NonFinite` otherwise).
    pub(crate) fn coordinate(&mut self) -> Result<f64, ReadError> {
        let t = self.expect_any()?;
        let v: f64 = parse(self.format, &t, "coordinate")?;
        if !v.is_finite() || !(v as f32).is_finite() {
            return Err(ReadError::NonFinite {
                format: self.format,
                location: t.loc(),
            });
        }
        Ok(v)
    }

    /// Skips a `{ ... }` block whose `{` was just read, nested blocks included.
    pub(crate) fn skip_block(&mut self) -> Result<(), ReadError> {
        let mut depth = 1usize;
        while depth > 0 {
            let t = self.expect_any()?;
            if t.is("{") {
                depth += 1;
            } else if t.is("}") {
                depth -= 1;
            }
        }
        Ok(())
    }
}

/// `t` parsed as a `T`, or `Malformed` naming `what`.
pub(crate) fn parse<T: FromStr>(format: Format, t: &Token, what: &str) -> Result<T, ReadError> {
    std::str::from_utf8(t.text)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| {
            malformed(
                format,
                t.loc(),
                format!("`{}` is not a valid {what}", t.show()),
            )
        })
}
