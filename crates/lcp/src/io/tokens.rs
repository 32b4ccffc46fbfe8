//! A tokenizer for the text formats: whitespace-separated tokens with 1-based line numbers.

use crate::LcpError;

/// Splits text into whitespace-separated tokens and remembers the line of each.
pub(crate) struct Tokens<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    current: std::str::SplitWhitespace<'a>,
    /// The 1-based line of the last token returned (0 before the first).
    pub(crate) line: usize,
    comments: bool,
}

impl<'a> Tokens<'a> {
    /// A tokenizer over `text`; with `comments`, `#` starts a comment that runs to the end of
    /// its line.
    pub(crate) fn new(text: &'a str, comments: bool) -> Self {
        Tokens {
            lines: text.lines().enumerate(),
            current: "".split_whitespace(),
            line: 0,
            comments,
        }
    }

    /// The next token and its line, or `None` at the end of the text.
    pub(crate) fn next_token(&mut self) -> Option<(usize, &'a str)> {
        loop {
            if let Some(t) = self.current.next() {
                return Some((self.line, t));
            }
            let (i, line) = self.lines.next()?;
            self.line = i + 1;
            let line = if self.comments { line.split('#').next().unwrap_or("") } else { line };
            self.current = line.split_whitespace();
        }
    }

    /// Drops the tokens left on the current line (for free-text parts of a format).
    pub(crate) fn skip_rest_of_line(&mut self) {
        self.current = "".split_whitespace();
    }

    /// The next token, or a parse error saying what was expected.
    pub(crate) fn token(&mut self, what: &str) -> Result<(usize, &'a str), LcpError> {
        self.next_token().ok_or_else(|| LcpError::Parse {
            line: self.line,
            message: format!("unexpected end of input, expected {what}"),
        })
    }

    /// The next token, which must be `word`.
    pub(crate) fn expect(&mut self, word: &str) -> Result<(), LcpError> {
        let (line, t) = self.token(&format!("'{word}'"))?;
        if t == word {
            Ok(())
        } else {
            Err(LcpError::Parse { line, message: format!("expected '{word}', found '{t}'") })
        }
    }

    /// The next token as a floating-point number.
    pub(crate) fn number(&mut self, what: &str) -> Result<f64, LcpError> {
        let (line, t) = self.token(what)?;
        t.parse::<f64>().map_err(|_| LcpError::Parse {
            line,
            message: format!("expected a number for {what}, found '{t}'"),
        })
    }

    /// The next token as an integer, with its line.
    pub(crate) fn integer(&mut self, what: &str) -> Result<(usize, i64), LcpError> {
        let (line, t) = self.token(what)?;
        let v = t.parse::<i64>().map_err(|_| LcpError::Parse {
            line,
            message: format!("expected an integer for {what}, found '{t}'"),
        })?;
        Ok((line, v))
    }

    /// The next token as an integer >= `min`.
    pub(crate) fn count(&mut self, what: &str, min: i64) -> Result<usize, LcpError> {
        let (line, v) = self.integer(what)?;
        if v < min {
            return Err(LcpError::Parse {
                line,
                message: format!("{what} must be >= {min}, found {v}"),
            });
        }
        usize::try_from(v)
            .map_err(|_| LcpError::Parse { line, message: format!("{what} too large") })
    }

    /// The next token as a size n >= 1.
    pub(crate) fn size(&mut self, what: &str) -> Result<usize, LcpError> {
        self.count(what, 1)
    }

    /// A parse error at the current line.
    pub(crate) fn error(&self, message: String) -> LcpError {
        LcpError::Parse { line: self.line, message }
    }
}

/// What a format lets follow the last value of a problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Trailer {
    /// Nothing but whitespace.
    Nothing,
    /// A free-text comment, which must not start with a number (Siconos' LCP files).
    Comment,
    /// The flag `0` or `1` alone, which Siconos' former FC2D writer added (`isComplete`).
    Flag,
}

impl Tokens<'_> {
    /// Refuses data after the last value of a problem, `after`, except what `trailer` lets
    /// follow it.
    pub(crate) fn end(&mut self, after: &'static str, trailer: Trailer) -> Result<(), LcpError> {
        let Some((line, found)) = self.next_token() else { return Ok(()) };
        let refuse =
            |line, found: &str| LcpError::TrailingData { line, found: found.to_owned(), after };
        match trailer {
            Trailer::Comment if found.parse::<f64>().is_err() => Ok(()),
            Trailer::Flag if found == "0" || found == "1" => match self.next_token() {
                None => Ok(()),
                Some((line, found)) => Err(refuse(line, found)),
            },
            _ => Err(refuse(line, found)),
        }
    }
}

/// Refuses a number of values that could not possibly be in a text of `len` bytes (each
/// value takes at least two bytes with its separator), so that a corrupt size cannot make
/// a reader allocate without bound.
pub(crate) fn check_count(values: usize, len: usize, line: usize) -> Result<(), LcpError> {
    if values <= len / 2 + 1 {
        Ok(())
    } else {
        Err(LcpError::Parse {
            line,
            message: format!("{values} values announced, more than the input can hold"),
        })
    }
}
