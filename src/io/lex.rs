//! A small tokenizer shared by the readers: whitespace-separated tokens that remember their
//! line, with typed accessors that turn every problem into an [`IoError::Parse`] naming the
//! line. Nothing here indexes out of bounds or allocates according to a count read from the
//! file, so the readers built on it cannot panic or exhaust memory on arbitrary input.

use super::IoError;

/// One token and the 1-based line it is on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tok<'a> {
    pub s: &'a str,
    pub line: usize,
}

/// A cursor over the tokens of a text.
pub(crate) struct Lexer<'a> {
    toks: Vec<Tok<'a>>,
    pos: usize,
    /// Line reported for errors at the end of the input.
    last_line: usize,
}

impl<'a> Lexer<'a> {
    /// Tokenizes `lines` (numbered from `first_line`), dropping everything after `comment` on
    /// each line.
    pub fn new(lines: impl Iterator<Item = &'a str>, first_line: usize, comment: Option<char>) -> Self {
        let mut toks = Vec::new();
        let mut last_line = first_line;
        for (i, line) in lines.enumerate() {
            let line_no = first_line + i;
            last_line = line_no;
            let body = match comment.and_then(|c| line.find(c)) {
                Some(k) => &line[..k],
                None => line,
            };
            toks.extend(body.split_ascii_whitespace().map(|s| Tok { s, line: line_no }));
        }
        Lexer { toks, pos: 0, last_line }
    }

    /// Tokens not consumed yet.
    pub fn remaining(&self) -> usize {
        self.toks.len() - self.pos
    }

    /// The next token without consuming it.
    pub fn peek(&self) -> Option<Tok<'a>> {
        self.toks.get(self.pos).copied()
    }

    /// The line of the next token (or the last line at the end).
    pub fn line(&self) -> usize {
        self.peek().map_or(self.last_line, |t| t.line)
    }

    /// An error at the current position.
    pub fn error(&self, message: impl Into<String>) -> IoError {
        IoError::Parse { line: self.line(), message: message.into() }
    }

    /// The next token; `what` names what was expected, for the end-of-file error.
    pub fn next(&mut self, what: &str) -> Result<Tok<'a>, IoError> {
        match self.toks.get(self.pos) {
            Some(&t) => {
                self.pos += 1;
                Ok(t)
            }
            None => Err(IoError::Parse {
                line: self.last_line,
                message: format!("unexpected end of file (expected {what})"),
            }),
        }
    }

    /// Consumes the next token if it equals `word` (ASCII case-insensitive).
    pub fn eat(&mut self, word: &str) -> bool {
        if self.peek().is_some_and(|t| t.s.eq_ignore_ascii_case(word)) {
            self.pos += 1;
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
        if n > self.remaining() {
            self.pos = self.toks.len();
            return Err(IoError::Parse {
                line: self.last_line,
                message: format!("unexpected end of file (expected {n} values of {what})"),
            });
        }
        self.pos += n;
        Ok(())
    }

    /// Every remaining token on the line of the next token (at least one).
    pub fn rest_of_line(&mut self, what: &str) -> Result<&[Tok<'a>], IoError> {
        let first = self.next(what)?;
        let start = self.pos - 1;
        while self.peek().is_some_and(|t| t.line == first.line) {
            self.pos += 1;
        }
        Ok(&self.toks[start..self.pos])
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
    pub fn blank_line_before_next(&self) -> bool {
        match (self.pos.checked_sub(1).and_then(|p| self.toks.get(p)), self.peek()) {
            (Some(a), Some(b)) => b.line > a.line + 1,
            _ => true,
        }
    }
}

/// A token as a non-negative integer.
pub(crate) fn parse_usize(t: Tok<'_>, what: &str) -> Result<usize, IoError> {
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
