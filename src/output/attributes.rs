//! pathlab's attributes of an EXR file, read strictly: the header is scanned as written (the
//! `exr` crate keeps custom attributes in a map, where a second `pathlab:seed` silently replaces
//! the first), and every `pathlab:KEY` must be a text attribute, appear once, and be at most
//! `MAX_VALUE_BYTES` long. Numbers are parsed as what they are and range-checked: nothing is
//! cut to fewer bits. Every refusal names the file and the attribute.

use std::collections::BTreeMap;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

/// Longest value of a pathlab attribute (a scene path, a list of missing ranges).
pub const MAX_VALUE_BYTES: usize = 4096;
/// Longest header scanned (OpenEXR headers of pathlab's files are a few kB).
const MAX_HEADER_BYTES: u64 = 1 << 20;

/// A problem with a file's pathlab attributes.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct AttributeError {
    pub path: PathBuf,
    pub message: String,
}

/// The `pathlab:KEY` text attributes of one file.
#[derive(Debug, Clone, PartialEq)]
pub struct Attributes {
    path: PathBuf,
    values: BTreeMap<String, String>,
}

fn read_exact_or(r: &mut impl Read, buf: &mut [u8], what: &str) -> Result<(), String> {
    r.read_exact(buf).map_err(|_| format!("the OpenEXR header ends inside {what}"))
}

/// A null-terminated name of at most 255 bytes (OpenEXR's long-name limit).
fn read_name(r: &mut impl Read, consumed: &mut u64) -> Result<Vec<u8>, String> {
    let mut name = Vec::new();
    loop {
        let mut b = [0u8; 1];
        read_exact_or(r, &mut b, "an attribute name")?;
        *consumed += 1;
        if b[0] == 0 {
            return Ok(name);
        }
        if name.len() >= 255 {
            return Err("an attribute name in the OpenEXR header is longer than 255 bytes".into());
        }
        name.push(b[0]);
    }
}

/// The header of a single-part OpenEXR file as it stands in the file.
pub(crate) struct RawHeader {
    /// Every attribute's (name, type, value bytes), in file order, duplicates included.
    pub records: Vec<(String, String, Vec<u8>)>,
    /// Bytes from the start of the file to the end of the header (its terminating null).
    pub end: usize,
}

/// Scans the header of a single-part OpenEXR file.
pub(crate) fn scan(r: &mut impl Read) -> Result<RawHeader, String> {
    let mut head = [0u8; 8];
    read_exact_or(r, &mut head, "the magic number")?;
    if head[..4] != [0x76, 0x2f, 0x31, 0x01] {
        return Err("wrong magic number".into());
    }
    let flags = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
    if flags & 0x1000 != 0 {
        return Err("a multi-part OpenEXR file; pathlab writes and reads single-part files".into());
    }
    let mut consumed = 8u64;
    let mut attributes = Vec::new();
    loop {
        let name = read_name(r, &mut consumed)?;
        if name.is_empty() {
            return Ok(RawHeader { records: attributes, end: consumed as usize });
        }
        let kind = read_name(r, &mut consumed)?;
        let mut size = [0u8; 4];
        read_exact_or(r, &mut size, "an attribute size")?;
        let size = i32::from_le_bytes(size);
        consumed += 4;
        let name = String::from_utf8_lossy(&name).into_owned();
        if size < 0 || consumed + size as u64 > MAX_HEADER_BYTES {
            return Err(format!("attribute `{name}` claims {size} bytes"));
        }
        let mut value = vec![0u8; size as usize];
        read_exact_or(r, &mut value, &format!("attribute `{name}`"))?;
        consumed += size as u64;
        attributes.push((name, String::from_utf8_lossy(&kind).into_owned(), value));
    }
}

impl Attributes {
    /// Reads and checks the pathlab attributes of `path`.
    pub fn read(path: &Path) -> Result<Attributes, AttributeError> {
        let fail = |message: String| AttributeError { path: path.to_path_buf(), message };
        let file = std::fs::File::open(path).map_err(|e| fail(format!("cannot open it ({e})")))?;
        let raw = scan(&mut BufReader::new(file)).map_err(|m| fail(format!("not a readable OpenEXR file ({m})")))?;
        let mut values = BTreeMap::new();
        for (name, kind, value) in raw.records {
            let Some(key) = name.strip_prefix("pathlab:") else { continue };
            if kind != "string" {
                return Err(fail(format!("pathlab:{key} is of type `{kind}`, not text")));
            }
            if value.len() > MAX_VALUE_BYTES {
                return Err(fail(format!("pathlab:{key} is {} bytes long (at most {MAX_VALUE_BYTES})", value.len())));
            }
            let text = String::from_utf8(value).map_err(|_| fail(format!("pathlab:{key} is not UTF-8 text")))?;
            if values.insert(key.to_string(), text).is_some() {
                return Err(fail(format!("pathlab:{key} appears more than once in the header")));
            }
        }
        Ok(Attributes { path: path.to_path_buf(), values })
    }

    /// The attributes as key-value pairs, sorted by key.
    pub fn metadata(&self) -> Vec<(String, String)> {
        self.values.iter().map(|(k, v)| (k.clone(), v.clone())).collect()
    }

    fn fail(&self, message: String) -> AttributeError {
        AttributeError { path: self.path.clone(), message }
    }

    /// The value of `pathlab:KEY`, if present.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.values.get(key).map(String::as_str)
    }

    /// The value of `pathlab:KEY`, which must be present.
    pub fn text(&self, key: &str) -> Result<&str, AttributeError> {
        self.get(key).ok_or_else(|| self.fail(format!("header attribute pathlab:{key} missing")))
    }

    /// `pathlab:KEY` as a whole number from 0 to `max` (canonical decimal: no sign, spaces or
    /// leading zeros).
    pub fn whole(&self, key: &str, max: u64) -> Result<u64, AttributeError> {
        let v = self.text(key)?;
        parse_whole(v, max).ok_or_else(|| self.fail(format!("pathlab:{key} is `{}`, not a whole number from 0 to {max}", shorten(v))))
    }

    /// Like `whole`, `None` when the attribute is absent.
    pub fn whole_opt(&self, key: &str, max: u64) -> Result<Option<u64>, AttributeError> {
        match self.get(key) {
            None => Ok(None),
            Some(_) => self.whole(key, max).map(Some),
        }
    }

    /// `pathlab:KEY` as a finite number, at least `min`.
    pub fn real(&self, key: &str, min: f64) -> Result<f64, AttributeError> {
        let v = self.text(key)?;
        match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() && x >= min => Ok(x),
            _ => Err(self.fail(format!("pathlab:{key} is `{}`, not a finite number of at least {min}", shorten(v)))),
        }
    }
}

/// Decimal digits only, at most `max`.
fn parse_whole(v: &str, max: u64) -> Option<u64> {
    if v.is_empty() || !v.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // Canonical decimal only: no leading zeros.
    v.parse::<u64>().ok().filter(|&n| n <= max && n.to_string() == v)
}

/// A value as quoted in a message (long ones cut).
fn shorten(v: &str) -> String {
    if v.chars().count() > 40 { format!("{}…", v.chars().take(40).collect::<String>()) } else { v.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_are_parsed_as_what_they_are() {
        assert_eq!(parse_whole("4294967298", u32::MAX as u64), None);
        assert_eq!(parse_whole("4294967295", u32::MAX as u64), Some(u32::MAX as u64));
        assert_eq!(parse_whole("18446744073709551615", u64::MAX), Some(u64::MAX));
        assert_eq!(parse_whole("18446744073709551616", u64::MAX), None);
        for bad in ["", "-1", "+1", " 1", "1e3", "0x10", "NaN", "01", "00"] {
            assert_eq!(parse_whole(bad, u64::MAX), None, "{bad}");
        }
    }
}
