//! Pieces shared by the readers: line and token scanning over bytes, number parsing, and
//! building errors that carry the file name and position.
//!
//! The readers work on the whole file in memory and never build `String`s for the data:
//! lines and tokens are sub-slices of the input, numbers are parsed straight from them.
//! Whitespace is ASCII space, tab, CR, vertical tab and form feed; a token that starts with
//! `#` ends the line (comments in OBJ and OFF, trailing or whole-line).
//!
//! A line ends at LF (Unix), CR LF (Windows) or a CR alone (classic Mac OS), in any mix;
//! line numbers in errors count every one of them, as text editors do. (Files of old Macs
//! put every record on one "line" for a reader that only knows LF: the first three numbers
//! of an OBJ would have been read and the rest of the file dropped in silence.)

use std::path::Path;

use crate::error::{Error, Location};

/// Names the file being read, so every error can say where it comes from.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Source<'a> {
    pub path: &'a Path,
}

impl<'a> Source<'a> {
    pub fn new(path: &'a Path) -> Self {
        Source { path }
    }

    /// A parse error on a 1-based line.
    pub fn at_line(&self, line: usize, message: impl Into<String>) -> Error {
        Error::parse(self.path, Location::Line(line), message)
    }

    /// A parse error at a 0-based byte offset.
    pub fn at_byte(&self, offset: usize, message: impl Into<String>) -> Error {
        Error::parse(self.path, Location::Byte(offset as u64), message)
    }

    /// A parse error about the file as a whole.
    pub fn whole(&self, message: impl Into<String>) -> Error {
        Error::parse(self.path, Location::File, message)
    }

    /// A parse error at `location`.
    pub fn at(&self, location: Location, message: impl Into<String>) -> Error {
        Error::parse(self.path, location, message)
    }
}

/// The UTF-8 byte-order mark some editors (Windows Notepad among them) put at the start of a
/// text file.
pub(crate) const BOM: &[u8] = b"\xef\xbb\xbf";

/// `bytes` without a leading UTF-8 byte-order mark.
pub(crate) fn strip_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(BOM).unwrap_or(bytes)
}

#[inline]
pub(crate) fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | 0x0b | 0x0c)
}

/// True when the input holds nothing but whitespace and line breaks.
pub(crate) fn is_blank(bytes: &[u8]) -> bool {
    bytes.iter().all(|&b| is_space(b) || b == b'\n')
}

/// Lines of a text, numbered from 1, without their line end (LF, CR LF or a lone CR).
pub(crate) struct Lines<'a> {
    bytes: &'a [u8],
    offset: usize,
    number: usize,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Lines {
            bytes,
            offset: 0,
            number: 0,
        }
    }

    /// Byte offset of the first byte not yet returned (the start of the next line).
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// Number of the last line returned (0 before the first).
    pub fn number(&self) -> usize {
        self.number
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        let rest = self.bytes.get(self.offset..)?;
        if rest.is_empty() {
            return None;
        }
        // One vectorised search for either byte: on the short lines of mesh files it costs a
        // tenth more than a search for LF alone (a third more on CR LF), which is about 1% of
        // reading a line.
        let (line, advance) = match memchr::memchr2(b'\n', b'\r', rest) {
            Some(n) if rest[n] == b'\r' && rest.get(n + 1) == Some(&b'\n') => (&rest[..n], n + 2),
            Some(n) => (&rest[..n], n + 1),
            None => (rest, rest.len()),
        };
        self.offset += advance;
        self.number += 1;
        Some((self.number, line))
    }
}

/// Whitespace-separated tokens of one line, stopping at a token that starts with `#`.
pub(crate) struct Tokens<'a> {
    rest: &'a [u8],
}

impl<'a> Tokens<'a> {
    #[inline]
    pub fn new(line: &'a [u8]) -> Self {
        Tokens { rest: line }
    }

    /// The part of the line not yet split into tokens.
    #[inline]
    pub fn remainder(&self) -> &'a [u8] {
        self.rest
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = &'a [u8];

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        let start = self.rest.iter().position(|&b| !is_space(b))?;
        let rest = &self.rest[start..];
        if rest[0] == b'#' {
            self.rest = &[];
            return None;
        }
        let end = rest.iter().position(|&b| is_space(b)).unwrap_or(rest.len());
        self.rest = &rest[end..];
        Some(&rest[..end])
    }
}

/// Tokens across lines, remembering the line of each (for the ascii bodies of PLY and STL,
/// where records need not follow line breaks).
pub(crate) struct Words<'a> {
    bytes: &'a [u8],
    offset: usize,
    line: usize,
}

impl<'a> Words<'a> {
    /// Tokens of `bytes[offset..]`, whose first line has number `line`.
    pub fn new(bytes: &'a [u8], offset: usize, line: usize) -> Self {
        Words {
            bytes,
            offset,
            line,
        }
    }

    /// Line of the last token returned, or of the end of the text after the last one.
    pub fn line(&self) -> usize {
        self.line
    }

    /// The next token and its line.
    #[inline]
    pub fn next_word(&mut self) -> Option<&'a [u8]> {
        let bytes = self.bytes;
        let mut i = self.offset;
        while i < bytes.len() {
            match bytes[i] {
                // A final line break does not start a line: errors at the end of the text
                // point at its last line.
                b'\n' => {
                    if i + 1 < bytes.len() {
                        self.line += 1;
                    }
                }
                // A CR alone ends a line too; before an LF it is part of that line end.
                b'\r' => {
                    if bytes.get(i + 1).is_some_and(|&next| next != b'\n') {
                        self.line += 1;
                    }
                }
                b if is_space(b) => {}
                _ => break,
            }
            i += 1;
        }
        if i >= bytes.len() {
            self.offset = i;
            return None;
        }
        let start = i;
        while i < bytes.len() && !is_space(bytes[i]) && bytes[i] != b'\n' {
            i += 1;
        }
        self.offset = i;
        Some(&bytes[start..i])
    }
}

/// The 1-based number of the line that holds byte `offset` of `bytes`, counting line ends as
/// [`Lines`] does (for errors found without walking the lines one by one).
pub(crate) fn line_at(bytes: &[u8], offset: usize) -> usize {
    let head = &bytes[..offset.min(bytes.len())];
    let line_feeds = memchr::memchr_iter(b'\n', head).count();
    // Looks one byte past `head`: a CR just before `offset` whose LF is at `offset` is the
    // start of that line end, not a line end of its own.
    let lone_returns = memchr::memchr_iter(b'\r', head)
        .filter(|&i| bytes.get(i + 1) != Some(&b'\n'))
        .count();
    1 + line_feeds + lone_returns
}

/// Parses a decimal floating-point number (Rust syntax: `1`, `-2.5`, `.5`, `1e-3`, `inf`,
/// `NaN`); callers reject non-finite values with a message of their own.
///
/// Always correctly rounded: the common short decimals take an exact fast path, everything
/// else (such as the 17 significant digits of shortest round-trip output) goes to
/// `fast-float2`, the Eisel-Lemire algorithm the standard library's parser also uses, which
/// reads the bytes without first checking them as UTF-8.
#[inline]
pub(crate) fn parse_f64(token: &[u8]) -> Option<f64> {
    match parse_short_decimal(token) {
        Some(x) => Some(x),
        None => fast_float2::parse(token).ok(),
    }
}

/// The number at the start of `text` and how many bytes it used, as [`parse_f64`] reads it
/// (correctly rounded, so the same bits). Straight to `fast-float2`, which has Clinger's fast
/// path inside: most files print 17 significant digits, beyond that path, and trying it
/// first here only cost a second scan.
#[inline]
fn f64_prefix(text: &[u8]) -> Option<(f64, usize)> {
    fast_float2::parse_partial(text).ok()
}

/// The three coordinates at the start of a vertex line when they are finite numbers
/// separated by whitespace, read without splitting the line into tokens first; `None` sends
/// the line to [`vertex`], which reads what this cannot and words the errors.
#[inline]
pub(crate) fn vertex_line(line: &[u8]) -> Option<[f64; 3]> {
    let mut rest = line;
    let mut p = [0.0; 3];
    for x in &mut p {
        let start = rest.iter().position(|&b| !is_space(b))?;
        rest = &rest[start..];
        let (value, used) = f64_prefix(rest)?;
        if used == 0 || !value.is_finite() || rest.get(used).is_some_and(|&b| !is_space(b)) {
            return None;
        }
        *x = value;
        rest = &rest[used..];
    }
    Some(p)
}

/// Powers of ten that are exact in an `f64`.
const EXACT_POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The decimal digit `bytes[i]`, if it is one.
#[inline]
fn digit_at(bytes: &[u8], i: usize) -> Option<u8> {
    bytes
        .get(i)
        .map(|b| b.wrapping_sub(b'0'))
        .filter(|&d| d < 10)
}

/// Appends the decimal digits from `bytes[*i]` on to `significand` (wrapping), moving `i`
/// past them; returns how many there were.
#[inline]
fn append_digits(bytes: &[u8], i: &mut usize, significand: &mut u64) -> usize {
    let start = *i;
    while let Some(d) = digit_at(bytes, *i) {
        *significand = significand.wrapping_mul(10).wrapping_add(u64::from(d));
        *i += 1;
    }
    *i - start
}

/// Clinger's fast path (W. D. Clinger, "How to Read Floating Point Numbers Accurately",
/// PLDI 1990): when the decimal significand m fits in 53 bits and the power of ten 10^e has
/// |e| <= 22, both are exact doubles and one IEEE multiplication or division rounds m·10^e
/// correctly. Mesh files are almost entirely such numbers; `None` sends the rest (and
/// anything malformed) to the full parser.
#[inline]
fn parse_short_decimal(token: &[u8]) -> Option<f64> {
    match short_decimal_prefix(token) {
        Some((x, used)) if used == token.len() => Some(x),
        _ => None,
    }
}

/// The number at the start of `text` by Clinger's fast path (see [`parse_short_decimal`]),
/// and how many bytes it used; `None` when it does not start with such a number.
#[inline]
pub(crate) fn short_decimal_prefix(text: &[u8]) -> Option<(f64, usize)> {
    let (negative, sign_bytes) = match text.first()? {
        b'-' => (true, 1),
        b'+' => (false, 1),
        _ => (false, 0),
    };
    let bytes = &text[sign_bytes..];
    let mut significand: u64 = 0;
    let mut i = 0;
    let integer_digits = append_digits(bytes, &mut i, &mut significand);
    let mut fraction_digits = 0usize;
    if bytes.get(i) == Some(&b'.') {
        i += 1;
        fraction_digits = append_digits(bytes, &mut i, &mut significand);
    }
    let digits = integer_digits + fraction_digits;
    // 19 decimal digits always fit in a u64, so the wrapping arithmetic above was exact.
    if digits == 0 || digits > 19 || significand > 1 << 53 {
        return None;
    }
    let mut exponent = -(fraction_digits as i64);
    if let Some(b'e' | b'E') = bytes.get(i) {
        i += 1;
        let (exponent_negative, start) = match bytes.get(i) {
            Some(b'-') => (true, i + 1),
            Some(b'+') => (false, i + 1),
            _ => (false, i),
        };
        i = start;
        let mut value: i64 = 0;
        while let Some(d) = digit_at(bytes, i) {
            // Anything past 4 digits is far outside the fast range; cap to avoid overflow.
            value = (value * 10 + i64::from(d)).min(100_000);
            i += 1;
        }
        if i == start {
            return None;
        }
        exponent += if exponent_negative { -value } else { value };
    }
    let m = significand as f64;
    let magnitude = match exponent {
        0 => m,
        1..=22 => m * EXACT_POWERS_OF_TEN[exponent as usize],
        -22..=-1 => m / EXACT_POWERS_OF_TEN[(-exponent) as usize],
        _ => return None,
    };
    Some((
        if negative { -magnitude } else { magnitude },
        sign_bytes + i,
    ))
}

/// True when `token` is a decimal integer with an optional sign, whatever its size: tells a
/// number too large for [`parse_i64`] from a word.
pub(crate) fn is_integer_token(token: &[u8]) -> bool {
    let digits = match token.first() {
        Some(b'-' | b'+') => &token[1..],
        _ => token,
    };
    !digits.is_empty() && digits.iter().all(u8::is_ascii_digit)
}

/// A count (of vertices, faces, an element's records) that must be a non-negative integer,
/// or a message that says what is wrong with `token`: negative, too large, or not an integer.
/// `what` names the count ("vertex count", "element count").
pub(crate) fn parse_count(token: &[u8], what: &str) -> Result<usize, String> {
    match parse_i64(token) {
        Some(n) if n < 0 => Err(format!(
            "{what} {n} is not a non-negative integer (a count cannot be negative)"
        )),
        Some(n) => usize::try_from(n).map_err(|_| format!("{what} {n} is too large")),
        None if is_integer_token(token) => {
            if token.starts_with(b"-") {
                Err(format!(
                    "{what} '{}' is not a non-negative integer (a count cannot be negative)",
                    show(token)
                ))
            } else {
                Err(format!("{what} '{}' is too large", show(token)))
            }
        }
        None => Err(format!(
            "{what} '{}' is not a non-negative integer",
            show(token)
        )),
    }
}

/// Parses a decimal integer with an optional sign.
#[inline]
pub(crate) fn parse_i64(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        b'+' => (false, &token[1..]),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i64 = 0;
    for &d in digits {
        let digit = d.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(i64::from(digit))?;
    }
    Some(if negative { -value } else { value })
}

/// A token as it should appear in a message: lossy UTF-8, cut after 40 bytes and marked
/// with "…" (a number of 300 digits would otherwise fill the terminal).
pub(crate) fn show(token: &[u8]) -> String {
    const LIMIT: usize = 40;
    if token.len() > LIMIT {
        format!("{}…", String::from_utf8_lossy(&token[..LIMIT]))
    } else {
        String::from_utf8_lossy(token).into_owned()
    }
}

/// Parses a coordinate, rejecting non-numeric and non-finite values.
///
/// The error message names what was expected (`what`, e.g. "x coordinate of vertex 3").
#[inline]
pub(crate) fn coordinate(token: Option<&[u8]>, what: impl Fn() -> String) -> Result<f64, String> {
    let Some(token) = token else {
        return Err(format!("missing {}", what()));
    };
    match parse_f64(token) {
        Some(x) if x.is_finite() => Ok(x),
        Some(_) => Err(format!("{} is NaN or infinite ('{}')", what(), show(token))),
        None => Err(format!(
            "non-numeric token '{}' where the {} was expected",
            show(token),
            what()
        )),
    }
}

/// Reads the three coordinates of a vertex from `tokens`.
#[inline]
pub(crate) fn vertex<'a>(
    tokens: &mut impl Iterator<Item = &'a [u8]>,
    index: usize,
) -> Result<[f64; 3], String> {
    let x = coordinate(tokens.next(), || format!("x coordinate of vertex {index}"))?;
    let y = coordinate(tokens.next(), || format!("y coordinate of vertex {index}"))?;
    let z = coordinate(tokens.next(), || format!("z coordinate of vertex {index}"))?;
    Ok([x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_numbered_and_keep_no_newline() {
        let lines: Vec<_> = Lines::new(b"a\r\nb\n\nc").collect();
        assert_eq!(
            lines,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
    }

    #[test]
    fn a_lone_carriage_return_ends_a_line() {
        let text = b"a\rb\r\rc\r\nd\ne\r";
        let lines: Vec<_> = Lines::new(text).collect();
        assert_eq!(
            lines,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..]),
                (5, &b"d"[..]),
                (6, &b"e"[..])
            ]
        );
        // The line of every byte, as the lines number them.
        let expected = [1, 1, 2, 2, 3, 4, 4, 4, 5, 5, 6, 6, 7];
        for (offset, &line) in expected.iter().enumerate() {
            assert_eq!(line_at(text, offset), line, "byte {offset}");
        }
        let mut w = Words::new(b"a\rb\r\n c\r", 0, 1);
        assert_eq!(w.next_word(), Some(&b"a"[..]));
        assert_eq!(w.next_word(), Some(&b"b"[..]));
        assert_eq!(w.line(), 2);
        assert_eq!(w.next_word(), Some(&b"c"[..]));
        assert_eq!(w.line(), 3);
        assert_eq!(w.next_word(), None);
        assert_eq!(w.line(), 3);
    }

    #[test]
    fn counts_say_what_is_wrong() {
        let count = |t: &str| parse_count(t.as_bytes(), "vertex count");
        assert_eq!(count("12"), Ok(12));
        assert_eq!(count("+0"), Ok(0));
        assert_eq!(
            count("-3"),
            Err(
                "vertex count -3 is not a non-negative integer (a count cannot be negative)".into()
            )
        );
        assert_eq!(
            count("-99999999999999999999"),
            Err(
                "vertex count '-99999999999999999999' is not a non-negative integer (a count \
                 cannot be negative)"
                    .into()
            )
        );
        assert_eq!(
            count("99999999999999999999"),
            Err("vertex count '99999999999999999999' is too large".into())
        );
        assert_eq!(
            count("3.5"),
            Err("vertex count '3.5' is not a non-negative integer".into())
        );
    }

    #[test]
    fn long_tokens_are_cut_in_messages() {
        let digits = "9".repeat(300);
        assert_eq!(show(digits.as_bytes()), format!("{}…", &digits[..40]));
        assert_eq!(show(b"short"), "short");
    }

    #[test]
    fn tokens_stop_at_comments() {
        let t: Vec<_> = Tokens::new(b"  v 1\t2 #3 4").collect();
        assert_eq!(t, vec![&b"v"[..], b"1", b"2"]);
        assert_eq!(Tokens::new(b"# all comment").count(), 0);
    }

    #[test]
    fn words_track_lines() {
        let mut w = Words::new(b"a b\n\n c\n", 0, 1);
        assert_eq!(w.next_word(), Some(&b"a"[..]));
        assert_eq!(w.next_word(), Some(&b"b"[..]));
        assert_eq!(w.line(), 1);
        assert_eq!(w.next_word(), Some(&b"c"[..]));
        assert_eq!(w.line(), 3);
        assert_eq!(w.next_word(), None);
        assert_eq!(w.line(), 3);
    }

    #[test]
    fn integers_parse_with_sign_and_reject_overflow() {
        assert_eq!(parse_i64(b"-12"), Some(-12));
        assert_eq!(parse_i64(b"+7"), Some(7));
        assert_eq!(parse_i64(b"-"), None);
        assert_eq!(parse_i64(b"1x"), None);
        assert_eq!(parse_i64(b"99999999999999999999"), None);
    }

    #[test]
    fn fast_float_path_matches_the_standard_parser() {
        let cases = [
            "0",
            "-0",
            "+1",
            "1.",
            ".5",
            "-.5",
            "0.1",
            "123.456",
            "-0.0378297",
            "1e5",
            "1E-5",
            "2.5e+3",
            "9007199254740993",
            "9007199254740992",
            "0.30000000000000004",
            "1234567890123456789",
            "12345678901234567890",
            "1e22",
            "1e23",
            "1e-22",
            "1e-23",
            "4.9e-324",
            "1.7976931348623157e308",
            "00000000000000000001.5",
            "1e",
            "e5",
            ".",
            "-",
            "1.2.3",
            "1e+",
            "inf",
            "-infinity",
            "NaN",
            "1_0",
            "0x10",
            "",
        ];
        for c in cases {
            let ours = parse_f64(c.as_bytes());
            let std: Option<f64> = c.parse().ok();
            assert_eq!(ours.map(f64::to_bits), std.map(f64::to_bits), "{c}");
        }
        // Many short decimals as exporters print them.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            if !x.is_finite() {
                continue;
            }
            let scaled = (state % 2_000_000) as f64 / 1000.0 - 1000.0;
            for s in [
                format!("{x}"),
                format!("{x:e}"),
                format!("{scaled:.6}"),
                format!("{:.3e}", x),
                format!("{}", scaled as f32),
            ] {
                let ours = parse_f64(s.as_bytes()).map(f64::to_bits);
                let std = s.parse::<f64>().ok().map(f64::to_bits);
                assert_eq!(ours, std, "{s}");
            }
        }
    }

    #[test]
    fn vertex_lines_read_as_their_tokens_do() {
        let lines = [
            "1 2 3",
            "  -0.002118901526682305 -0.04000656638672886\t-0.0009573251918796522 ",
            "1 2 3 0.5 0.5 1",
            "1 2 3#c",
            "1 2 # 3",
            "1 2",
            "1 2 nan",
            "1 2 1e999",
            "1 2 1.5e",
            "+1 .5 5.",
            "1 2 3x",
            "1,2 3 4",
            "0x10 1 2",
            "inf 1 2",
            "",
        ];
        for line in lines {
            // `None` leaves the line to the token path, always right.
            if let Some(p) = vertex_line(line.as_bytes()) {
                let tokens = vertex(&mut Tokens::new(line.as_bytes()), 0);
                assert_eq!(Ok(p), tokens, "{line}");
            }
        }
        assert!(vertex_line(lines[1].as_bytes()).is_some());
        assert_eq!(vertex_line(b"1 2 3x"), None);
        assert_eq!(vertex_line(b"1 2 nan"), None);
        assert_eq!(vertex_line(b"1 2 3 4"), Some([1.0, 2.0, 3.0]));
    }

    #[test]
    fn coordinates_reject_nan_and_words() {
        let what = || "x".to_string();
        assert_eq!(coordinate(Some(b"1e-3"), what), Ok(1e-3));
        assert!(
            coordinate(Some(b"nan"), what)
                .unwrap_err()
                .contains("NaN or infinite")
        );
        assert!(
            coordinate(Some(b"1e999"), what)
                .unwrap_err()
                .contains("NaN or infinite")
        );
        assert!(
            coordinate(Some(b"abc"), what)
                .unwrap_err()
                .contains("non-numeric token 'abc'")
        );
        assert!(coordinate(None, what).unwrap_err().contains("missing x"));
    }
}
