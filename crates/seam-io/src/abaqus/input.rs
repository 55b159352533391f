//! The lines of an input file and the files it includes: comments and blank
//! lines dropped, keyword lines (continued over lines ending with a comma)
//! split into a name and options, `*INCLUDE` followed.

use std::path::{Path, PathBuf};

use super::{InpError, Loc};

/// The most `*INCLUDE`s one reading follows, and how deep they nest.
const MAX_INCLUDES: usize = 10_000;
const MAX_DEPTH: usize = 64;

/// A keyword line: `*ELEMENT, TYPE=C3D8, ELSET=EALL`.
#[derive(Debug)]
pub(super) struct Keyword {
    /// The keyword in upper case without spaces: `ELEMENT`, `SOLIDSECTION`.
    pub name: String,
    /// The options in order: name in upper case without spaces, value as
    /// written without quotes (empty for a flag such as `GENERATE`).
    pub options: Vec<(String, String)>,
    /// Where it is.
    pub at: Loc,
}

impl Keyword {
    /// The value of option `name` (upper case), if given.
    pub fn option(&self, name: &str) -> Option<&str> {
        self.options.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }

    /// Whether option `name` is given (as a flag or with a value).
    pub fn flag(&self, name: &str) -> bool {
        self.options.iter().any(|(n, _)| n == name)
    }
}

/// One meaningful line.
#[derive(Debug)]
pub(super) enum Line {
    Keyword(Keyword),
    /// A data line as written (trimmed), with where it is.
    Data(String, Loc),
}

/// One file being read.
struct Source {
    file: u32,
    text: Vec<u8>,
    pos: usize,
    line: u32,
    /// The canonical path, for include cycles (`None` for bytes in memory).
    canonical: Option<PathBuf>,
}

/// The stack of files being read: the main input and the includes open
/// inside it.
pub(super) struct Sources {
    stack: Vec<Source>,
    /// The path of every file read so far (`None`: the bytes given to
    /// [`crate::read_inp`]); [`Loc::file`] indexes it.
    pub files: Vec<Option<PathBuf>>,
    /// The bytes of every file read so far.
    pub bytes: usize,
    includes: usize,
}

impl Sources {
    /// The input `text`, read from `path` (`None`: in memory).
    pub fn new(text: Vec<u8>, path: Option<PathBuf>) -> Sources {
        let canonical = path.as_ref().map(|p| p.canonicalize().unwrap_or_else(|_| p.clone()));
        let bytes = text.len();
        Sources {
            stack: vec![Source { file: 0, text, pos: 0, line: 0, canonical }],
            files: vec![path],
            bytes,
            includes: 0,
        }
    }

    /// An error at `at`.
    pub fn error(&self, at: Loc, message: impl Into<String>) -> InpError {
        InpError::new(message).at(self.files[at.file as usize].clone(), at.line)
    }

    /// "part.inp:12" or "line 12" (for the bytes given to [`crate::read_inp`]).
    pub fn describe(&self, at: Loc) -> String {
        match &self.files[at.file as usize] {
            Some(path) => format!("{}:{}", path.display(), at.line),
            None => format!("line {}", at.line),
        }
    }

    /// The next raw line of the innermost file (without its end), where it
    /// is; the files that end are closed.
    fn raw_line(&mut self) -> Option<(String, Loc)> {
        loop {
            let source = self.stack.last_mut()?;
            if source.pos >= source.text.len() {
                self.stack.pop();
                continue;
            }
            let rest = &source.text[source.pos..];
            let end = memchr::memchr(b'\n', rest).unwrap_or(rest.len());
            let line = String::from_utf8_lossy(&rest[..end]).into_owned();
            source.pos += end + 1;
            source.line = source.line.saturating_add(1);
            return Some((line, Loc { file: source.file, line: source.line }));
        }
    }

    /// The next keyword or data line; `*INCLUDE` lines open their file and
    /// read on inside it.
    pub fn next(&mut self) -> Result<Option<Line>, InpError> {
        loop {
            let Some((raw, at)) = self.raw_line() else { return Ok(None) };
            let text = raw.trim();
            if text.is_empty() || text.starts_with("**") {
                continue;
            }
            if !text.starts_with('*') {
                return Ok(Some(Line::Data(text.to_string(), at)));
            }
            let mut whole = text.to_string();
            // A keyword line ending with a comma goes on on the next line.
            while whole.ends_with(',') {
                match self.peek_continuation(at.file) {
                    Some(next) => whole.push_str(&next),
                    None => break,
                }
            }
            let keyword = parse_keyword(&whole, at).map_err(|m| self.error(at, m))?;
            if keyword.name == "INCLUDE" {
                self.include(&keyword)?;
                continue;
            }
            return Ok(Some(Line::Keyword(keyword)));
        }
    }

    /// The next line of the same file if it continues a keyword line (not a
    /// keyword, comment or blank line), consumed.
    fn peek_continuation(&mut self, file: u32) -> Option<String> {
        let source = self.stack.last_mut().filter(|s| s.file == file)?;
        let rest = source.text.get(source.pos..)?;
        let end = memchr::memchr(b'\n', rest).unwrap_or(rest.len());
        let line = String::from_utf8_lossy(&rest[..end]);
        let line = line.trim();
        if line.is_empty() || line.starts_with('*') {
            return None;
        }
        let line = line.to_string();
        source.pos += end + 1;
        source.line = source.line.saturating_add(1);
        Some(line)
    }

    /// Opens the file of `*INCLUDE, INPUT=…`, relative to the including file.
    fn include(&mut self, keyword: &Keyword) -> Result<(), InpError> {
        let at = keyword.at;
        let Some(name) = keyword.option("INPUT").filter(|n| !n.is_empty()) else {
            return Err(self.error(at, "*INCLUDE without INPUT=FILE"));
        };
        let Some(including) = self.files[at.file as usize].clone() else {
            return Err(self.error(
                at,
                format!(
                    "*INCLUDE, INPUT={name}: input read from memory has no directory to find the file in; read it \
                     with read_inp_file"
                ),
            ));
        };
        if self.includes >= MAX_INCLUDES || self.stack.len() >= MAX_DEPTH {
            return Err(self.error(
                at,
                format!(
                    "*INCLUDE, INPUT={name}: more than {MAX_INCLUDES} includes or {MAX_DEPTH} levels deep"
                ),
            ));
        }
        let path = match Path::new(name).is_absolute() {
            true => PathBuf::from(name),
            false => including.parent().unwrap_or(Path::new("")).join(name),
        };
        let text = crate::read_regular_file(&path).map_err(|e| {
            self.error(at, format!("cannot read the included file {}: {}", path.display(), lowercase(&e)))
        })?;
        let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
        if let Some(open) = self.stack.iter().position(|s| s.canonical.as_ref() == Some(&canonical)) {
            let chain: Vec<String> = self.stack[open..]
                .iter()
                .map(|s| self.files[s.file as usize].as_ref().map_or("?".into(), |p| p.display().to_string()))
                .chain([path.display().to_string()])
                .collect();
            return Err(self.error(at, format!("include cycle: {}", chain.join(" includes "))));
        }
        self.includes += 1;
        self.bytes = self.bytes.saturating_add(text.len());
        let file = u32::try_from(self.files.len()).unwrap_or(u32::MAX);
        self.files.push(Some(path));
        self.stack.push(Source { file, text, pos: 0, line: 0, canonical: Some(canonical) });
        Ok(())
    }
}

/// An I/O error in words, lower case first ("no such file or directory").
fn lowercase(e: &std::io::Error) -> String {
    let text = e.to_string();
    let text = text.split(" (os error").next().unwrap_or(&text).to_string();
    let mut chars = text.chars();
    match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => text,
    }
}

/// Splits `text` at commas outside double quotes.
pub(super) fn split_fields(text: &str) -> Vec<&str> {
    let mut fields = Vec::new();
    let mut quoted = false;
    let mut start = 0;
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => {
                fields.push(text[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    fields.push(text[start..].trim());
    fields
}

/// Upper case without blanks: how Abaqus compares keyword and option names.
fn normalise(name: &str) -> String {
    name.chars().filter(|c| !c.is_whitespace()).map(|c| c.to_ascii_uppercase()).collect()
}

/// `*NAME, OPT=VALUE, FLAG, …` (the leading `*` included).
fn parse_keyword(text: &str, at: Loc) -> Result<Keyword, String> {
    let mut fields = split_fields(&text[1..]).into_iter();
    let name = normalise(fields.next().unwrap_or(""));
    if name.is_empty() {
        return Err(format!("a keyword line without a keyword: {:?}", shorten(text)));
    }
    let mut options = Vec::new();
    for field in fields.filter(|f| !f.is_empty()) {
        let (key, value) = match field.split_once('=') {
            Some((key, value)) => (normalise(key), value.trim().trim_matches('"').to_string()),
            None => (normalise(field), String::new()),
        };
        options.push((key, value));
    }
    Ok(Keyword { name, options, at })
}

/// At most 60 characters of `text`, for messages.
pub(super) fn shorten(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str) -> Vec<String> {
        let mut sources = Sources::new(text.as_bytes().to_vec(), None);
        let mut out = Vec::new();
        while let Some(line) = sources.next().unwrap() {
            out.push(match line {
                Line::Keyword(k) => format!("{}@{} {:?}", k.name, k.at.line, k.options),
                Line::Data(d, at) => format!("{d}@{}", at.line),
            });
        }
        out
    }

    #[test]
    fn keywords_are_normalised_and_continued() {
        let text = "** comment\n*Solid Section, elset=\"A b\",\n material=Steel\n\n1, 2\n*heading\n";
        assert_eq!(
            lines(text),
            ["SOLIDSECTION@2 [(\"ELSET\", \"A b\"), (\"MATERIAL\", \"Steel\")]", "1, 2@5", "HEADING@6 []"]
        );
    }

    #[test]
    fn fields_split_outside_quotes() {
        assert_eq!(split_fields(" a , \"b,c\" ,"), ["a", "\"b,c\"", ""]);
    }

    #[test]
    fn include_from_memory_is_refused() {
        let mut sources = Sources::new(b"*INCLUDE, INPUT=x.inp\n".to_vec(), None);
        let e = sources.next().unwrap_err();
        assert!(e.to_string().starts_with("line 1: *INCLUDE, INPUT=x.inp: input read from memory"), "{e}");
    }
}
