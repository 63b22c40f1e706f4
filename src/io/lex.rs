//! A small tokenizer shared by the readers: whitespace-separated tokens that remember their
//! line, with typed accessors that turn every problem into an [`IoError::Parse`] naming the
//! line. Tokens are found lazily, one at a time, as slices of the text (nothing is collected
//! per token, so reading takes memory for the mesh, not for the file's words). Nothing here
//! indexes out of bounds or allocates according to a count read from the file, so the readers
//! built on it cannot panic or exhaust memory on arbitrary input.

use super::IoError;

/// One token and the 1-based line it is on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tok<'a> {
    pub s: &'a str,
    pub line: usize,
}

/// A cursor over the tokens of a text.
pub(crate) struct Lexer<'a> {
    /// The text after the current line.
    rest: &'a str,
    /// What is left of the current line (its comment removed).
    line: &'a str,
    /// The current line's number.
    line_no: usize,
    /// The number of the text's first line.
    first_line: usize,
    comment: Option<char>,
    /// The next token, once found.
    peeked: Option<Tok<'a>>,
    /// Line of the last token consumed.
    prev_line: Option<usize>,
    /// The tokens of the last [`Lexer::rest_of_line`] (kept to reuse the allocation).
    line_toks: Vec<Tok<'a>>,
}

impl<'a> Lexer<'a> {
    /// A lexer over `text`, whose first line is numbered `first_line`; everything after
    /// `comment` on a line is dropped.
    pub fn new(text: &'a str, first_line: usize, comment: Option<char>) -> Self {
        Lexer {
            rest: text,
            line: "",
            // No line has been read yet: the first one read is `first_line`.
            line_no: first_line.wrapping_sub(1),
            first_line,
            comment,
            peeked: None,
            prev_line: None,
            line_toks: Vec::new(),
        }
    }

    /// The next whole line, raw (for headers and titles); `None` at the end of the text.
    /// Only valid before any token is read from that line.
    pub fn raw_line(&mut self) -> Option<&'a str> {
        debug_assert!(self.peeked.is_none() && self.line.is_empty());
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.find('\n') {
            Some(k) => (&self.rest[..k], &self.rest[k + 1..]),
            None => (self.rest, ""),
        };
        self.rest = rest;
        self.line_no = self.line_no.wrapping_add(1);
        Some(line.strip_suffix('\r').unwrap_or(line))
    }

    /// Finds the next token if it is not known yet.
    fn fill(&mut self) {
        if self.peeked.is_some() {
            return;
        }
        loop {
            // Bytes, not chars: ASCII whitespace bytes are never inside a multi-byte char, so
            // the slices end on char boundaries.
            let b = self.line.as_bytes();
            let start = b.iter().position(|c| !c.is_ascii_whitespace()).unwrap_or(b.len());
            if start < b.len() {
                let len = b[start..].iter().position(u8::is_ascii_whitespace).unwrap_or(b.len() - start);
                let end = start + len;
                self.peeked = Some(Tok { s: &self.line[start..end], line: self.line_no });
                self.line = &self.line[end..];
                return;
            }
            self.line = "";
            let Some(next) = self.raw_line() else { return };
            self.line = match self.comment.and_then(|c| next.find(c)) {
                Some(k) => &next[..k],
                None => next,
            };
        }
    }

    /// The last line of the text, once the end is reached (for end-of-file errors).
    fn end_line(&self) -> usize {
        self.line_no.max(self.first_line)
    }

    /// An upper bound of the number of tokens left (a token and its separator take at
    /// least two bytes), for bounding capacities by what the input can actually hold.
    pub fn max_tokens(&self) -> usize {
        (self.rest.len() + self.line.len()) / 2 + 1 + usize::from(self.peeked.is_some())
    }

    /// The next token without consuming it.
    pub fn peek(&mut self) -> Option<Tok<'a>> {
        self.fill();
        self.peeked
    }

    /// The line of the next token (or the last line at the end).
    pub fn line(&mut self) -> usize {
        match self.peek() {
            Some(t) => t.line,
            None => self.end_line(),
        }
    }

    /// An error at the current position.
    pub fn error(&mut self, message: impl Into<String>) -> IoError {
        IoError::Parse { line: self.line(), message: message.into() }
    }

    /// The end-of-file error, `what` naming what was expected.
    fn eof(&self, what: &str) -> IoError {
        IoError::Parse { line: self.end_line(), message: format!("unexpected end of file (expected {what})") }
    }

    /// The next token; `what` names what was expected, for the end-of-file error.
    pub fn next(&mut self, what: &str) -> Result<Tok<'a>, IoError> {
        self.fill();
        match self.peeked.take() {
            Some(t) => {
                self.prev_line = Some(t.line);
                Ok(t)
            }
            None => Err(self.eof(what)),
        }
    }

    /// Consumes the next token if it equals `word` (ASCII case-insensitive).
    pub fn eat(&mut self, word: &str) -> bool {
        if self.peek().is_some_and(|t| t.s.eq_ignore_ascii_case(word)) {
            self.prev_line = self.peeked.take().map(|t| t.line);
            true
        } else {
            false
        }
    }

    /// The next token as a non-negative integer.
    pub fn usize(&mut self, what: &str) -> Result<usize, IoError> {
        let t = self.next(what)?;
        parse_usize(t, what)
    }

    /// The next token as a floating-point number.
    pub fn f64(&mut self, what: &str) -> Result<f64, IoError> {
        let t = self.next(what)?;
        parse_f64(t, what)
    }

    /// Skips `n` tokens, failing if fewer are left.
    pub fn skip(&mut self, n: usize, what: &str) -> Result<(), IoError> {
        for _ in 0..n {
            if self.peek().is_none() {
                return Err(self.eof(&format!("{n} values of {what}")));
            }
            self.next(what)?;
        }
        Ok(())
    }

    /// Every remaining token on the line of the next token (at least one).
    pub fn rest_of_line(&mut self, what: &str) -> Result<&[Tok<'a>], IoError> {
        let first = self.next(what)?;
        self.line_toks.clear();
        self.line_toks.push(first);
        // The rest of the current line, without reading the next one.
        let toks = self.line.split_ascii_whitespace().map(|s| Tok { s, line: first.line });
        self.line_toks.extend(toks);
        self.line = "";
        Ok(&self.line_toks)
    }

    /// Skips tokens up to and including the first one equal to `word`.
    pub fn skip_past(&mut self, word: &str) -> Result<(), IoError> {
        loop {
            if self.next(word)?.s.eq_ignore_ascii_case(word) {
                return Ok(());
            }
        }
    }

    /// Whether there is a blank line between the previous token and the next one.
    pub fn blank_line_before_next(&mut self) -> bool {
        match (self.prev_line, self.peek()) {
            (Some(a), Some(b)) => b.line > a + 1,
            _ => true,
        }
    }
}

/// Appends to a vector that grows with the input, failing with
/// [`Error::OutOfMemory`](crate::Error::OutOfMemory) instead of aborting.
pub(crate) fn try_push<T>(v: &mut Vec<T>, item: T, what: &'static str) -> Result<(), IoError> {
    if v.len() == v.capacity() {
        v.try_reserve(1).map_err(|_| crate::alloc::out_of_memory::<T>(what, v.len().saturating_mul(2)))?;
    }
    v.push(item);
    Ok(())
}

/// An empty vector with room for `count` elements, or an out-of-memory error.
pub(crate) fn try_vec<T>(count: usize, what: &'static str) -> Result<Vec<T>, IoError> {
    Ok(crate::alloc::try_with_capacity(count, what)?)
}

/// A token as a non-negative integer.
pub(crate) fn parse_usize(t: Tok<'_>, what: &str) -> Result<usize, IoError> {
    // The common case, up to 19 decimal digits (no overflow in a u64), without std's checks.
    let b = t.s.as_bytes();
    if !b.is_empty() && b.len() <= 19 && b.iter().all(u8::is_ascii_digit) {
        let v = b.iter().fold(0u64, |v, &c| v * 10 + u64::from(c - b'0'));
        if let Ok(v) = usize::try_from(v) {
            return Ok(v);
        }
    }
    t.s.parse::<usize>().map_err(|_| IoError::Parse {
        line: t.line,
        message: format!("expected {what} (a non-negative integer), found '{}'", clip(t.s)),
    })
}

/// A token as a signed integer.
pub(crate) fn parse_i64(t: Tok<'_>, what: &str) -> Result<i64, IoError> {
    t.s.parse::<i64>().map_err(|_| IoError::Parse {
        line: t.line,
        message: format!("expected {what} (an integer), found '{}'", clip(t.s)),
    })
}

/// A token as a floating-point number (Rust's parser is correctly rounded, so a value written
/// with shortest round-trip formatting reads back bit-identical).
pub(crate) fn parse_f64(t: Tok<'_>, what: &str) -> Result<f64, IoError> {
    t.s.parse::<f64>().map_err(|_| IoError::Parse {
        line: t.line,
        message: format!("expected {what} (a number), found '{}'", clip(t.s)),
    })
}

/// A token shortened for an error message (at most 40 characters, on a char boundary).
pub(crate) fn clip(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((k, _)) => format!("{}...", &s[..k]),
        None => s.to_string(),
    }
}
