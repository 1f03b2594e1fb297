//! Seeded corruptions of the EXR files pathlab reads back (parts, checkpoints, references), for
//! the robustness tests (`tests/file_mutations.rs`): truncations, bit flips in the header and in
//! the data, rewritten attributes (64-bit edges, NaN, wrong types, duplicates, huge values),
//! missing, extra and mistyped channels, non-finite and negative values, wrapped sample ranges.
//!
//! A mutation that rewrites the file's content comes in two forms: as damage (the checksum left
//! as it was, so `pathlab:data_sha256` catches it) and forged (the checksum recomputed, as a
//! buggy or foreign writer would leave it), so that the specific validation is tested too.

use std::path::Path;

use exr::prelude::*;
use std::result::Result;

use super::attributes::scan;
use super::{content_sha256, OutputError, CHECKSUM_KEY};

/// What a reader must do with a mutant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expect {
    /// The file is wrong: a clean refusal naming it.
    Refuse,
    /// The damage may not matter (a flipped bit in a field nothing reads): a refusal, or a
    /// result identical to the unmutated file's.
    RefuseOrSame,
}

/// One corrupted file.
#[derive(Debug, Clone)]
pub struct Mutant {
    pub label: String,
    pub bytes: Vec<u8>,
    pub expect: Expect,
}

/// SplitMix64: a small seeded generator, so a failing case is reproduced from its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
}

/// The parsed file a rewrite starts from.
struct Parsed {
    size: (usize, usize),
    channels: Vec<AnyChannel<FlatSamples>>,
    metadata: Vec<(String, String)>,
}

fn parse(path: &Path) -> Result<Parsed, OutputError> {
    let fail = |message: String| OutputError::Read { path: path.to_path_buf(), message };
    let image = read_all_flat_layers_from_file(path).map_err(|e| fail(e.to_string()))?;
    let mut metadata = Vec::new();
    for (key, value) in image.attributes.other.iter().chain(&image.layer_data[0].attributes.other) {
        if let (Some(k), AttributeValue::Text(t)) = (key.to_string().strip_prefix("pathlab:"), value) {
            metadata.push((k.to_string(), t.to_string()));
        }
    }
    metadata.sort();
    let layer = image.layer_data.into_iter().next().ok_or_else(|| fail("no layer".into()))?;
    Ok(Parsed { size: (layer.size.width(), layer.size.height()), channels: layer.channel_data.list.into_vec(), metadata })
}

/// Writes `channels` with `metadata` (image attributes) and `extra` (layer attributes, where a
/// key already in `metadata` becomes a duplicate in the file) to bytes; `forge` recomputes the
/// checksum over what is written, else the original's checksum is kept.
fn write(parsed: &Parsed, channels: Vec<AnyChannel<FlatSamples>>, metadata: &[(String, String)], extra: &[(String, AttributeValue)], forge: bool) -> Option<Vec<u8>> {
    let channels = AnyChannels::sort(channels.into());
    let mut metadata: Vec<(String, String)> = metadata.iter().filter(|(k, _)| k != CHECKSUM_KEY).cloned().collect();
    let checksum = if forge {
        content_sha256(&metadata, &channels)
    } else {
        parsed.metadata.iter().find(|(k, _)| k == CHECKSUM_KEY).map(|(_, v)| v.clone()).unwrap_or_default()
    };
    metadata.push((CHECKSUM_KEY.to_string(), checksum));
    let mut layer_attributes = LayerAttributes::default();
    for (k, v) in extra {
        layer_attributes.other.insert(Text::from(format!("pathlab:{k}").as_str()), v.clone());
    }
    let layer = Layer::new(parsed.size, layer_attributes, Encoding::FAST_LOSSLESS, channels);
    let mut image = Image::from_layer(layer);
    for (k, v) in &metadata {
        image.attributes.other.insert(Text::from(format!("pathlab:{k}").as_str()), AttributeValue::Text(Text::from(v.as_str())));
    }
    let mut cursor = std::io::Cursor::new(Vec::new());
    image.write().to_buffered(&mut cursor).ok()?;
    Some(cursor.into_inner())
}

/// `bytes` with the values of the attributes named in `replace` replaced and the attribute
/// records `append` added at the end of the header, spliced into the header as written (the
/// `exr` crate will not write duplicate names or texts longer than its limits), the chunk
/// offsets that follow the header shifted to match.
fn splice(bytes: &[u8], replace: &[(String, Vec<u8>)], append: &[(String, String, Vec<u8>)], chunks: usize) -> Option<Vec<u8>> {
    let header = scan(&mut &bytes[..]).ok()?;
    let mut out = bytes[..8].to_vec();
    let mut record = |name: &[u8], kind: &[u8], value: &[u8]| {
        out.extend(name);
        out.push(0);
        out.extend(kind);
        out.push(0);
        out.extend((value.len() as i32).to_le_bytes());
        out.extend(value);
    };
    for (name, kind, old) in &header.records {
        let new = replace.iter().find(|(n, _)| n == name).map_or(old.as_slice(), |(_, v)| v.as_slice());
        record(name.as_bytes(), kind.as_bytes(), new);
    }
    for (name, kind, value) in append {
        record(name.as_bytes(), kind.as_bytes(), value);
    }
    out.push(0);
    let at = header.end;
    let delta = out.len() as i64 - at as i64;
    for k in 0..chunks {
        let offset = u64::from_le_bytes(bytes.get(at + 8 * k..at + 8 * k + 8)?.try_into().ok()?);
        out.extend(((offset as i64 + delta) as u64).to_le_bytes());
    }
    out.extend(bytes.get(at + 8 * chunks..)?);
    Some(out)
}

/// `bytes` with `pathlab:KEY` set to `value` and the checksum to `checksum`, spliced.
fn splice_text(bytes: &[u8], key: &str, value: &str, checksum: &str, chunks: usize) -> Option<Vec<u8>> {
    let replace = [(format!("pathlab:{key}"), value.as_bytes().to_vec()), (format!("pathlab:{CHECKSUM_KEY}"), checksum.as_bytes().to_vec())];
    splice(bytes, &replace, &[], chunks)
}

/// Chunks of the file's first part (the length of its offset table).
fn chunk_count(path: &Path) -> Option<usize> {
    exr::meta::MetaData::read_from_file(path, false).ok()?.headers.first().map(|h| h.chunk_count)
}

fn unwritable(path: &Path, what: &str) -> OutputError {
    OutputError::Encode { path: path.to_path_buf(), message: format!("cannot write a mutant with {what}") }
}


/// Values to write into an attribute: malformed numbers, 32- and 64-bit edges, a 100 kB text,
/// the value twice over.
fn bad_values(value: &str) -> Vec<String> {
    let mut v: Vec<String> = ["", "abc", "NaN", "inf", "-1", " 1", "01", "1e3", "4294967296", "4294967298", "18446744073709551615", "18446744073709551616"]
        .map(String::from)
        .into();
    v.push("x".repeat(100_000));
    v.push(format!("{value}{value}"));
    v
}

/// Whether `bad` is a valid, different value of a field that changes what a reader reports
/// (a forged file with it is not corrupt, only different): such rewrites are not generated.
fn legitimately_different(key: &str, bad: &str) -> bool {
    match key {
        "exposure" => bad.trim().parse::<f32>().is_ok_and(f32::is_finite),
        "render_seconds" => bad.trim().parse::<f64>().is_ok_and(|x| x.is_finite() && x >= 0.0),
        "display" => bad.parse::<crate::display::Transfer>().is_ok(),
        _ => false,
    }
}

/// How many mutants of each kind.
#[derive(Debug, Clone, Copy)]
pub struct Plan {
    /// Random bit flips in the header, and as many in the data.
    pub flips: usize,
    /// Bad values written into each pathlab attribute (drawn from `bad_values`).
    pub values_per_attribute: usize,
    /// Channels removed, retyped and given impossible values (drawn at random).
    pub channels: usize,
}

/// The mutants of `path` for this `seed`: a dozen truncations, bit flips, and the rewrites
/// described in the module documentation, as many as `plan` says.
pub fn mutants(path: &Path, seed: u64, plan: Plan) -> Result<Vec<Mutant>, OutputError> {
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io { path: path.to_path_buf(), source })?;
    let parsed = parse(path)?;
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    let end = scan(&mut &bytes[..]).map_err(|message| OutputError::Read { path: path.to_path_buf(), message })?.end;

    // Truncations, at the edges and inside header and data.
    let mut cuts = vec![0, 1, 4, 8, end.saturating_sub(1), end, end + 8, bytes.len() / 2, bytes.len() - 1];
    for _ in 0..4 {
        cuts.push(rng.below(bytes.len() as u64) as usize);
    }
    for cut in cuts {
        if cut < bytes.len() {
            out.push(Mutant { label: format!("truncated to {cut} of {} bytes", bytes.len()), bytes: bytes[..cut].to_vec(), expect: Expect::Refuse });
        }
    }
    // Bit flips: anything may happen but a wrong result.
    for (region, lo, hi) in [("header", 8, end), ("data", end, bytes.len())] {
        for _ in 0..plan.flips {
            let at = lo + rng.below((hi - lo) as u64) as usize;
            let bit = rng.below(8);
            let mut b = bytes.clone();
            b[at] ^= 1 << bit;
            out.push(Mutant { label: format!("bit {bit} of byte {at} flipped ({region})"), bytes: b, expect: Expect::RefuseOrSame });
        }
    }
    let same_channels = || parsed.channels.clone();
    // Rewritten attributes: bad values, removed, duplicated, of another type; damaged and forged.
    for (key, value) in parsed.metadata.iter().filter(|(k, _)| k != CHECKSUM_KEY) {
        let mut values = bad_values(value);
        while values.len() > plan.values_per_attribute {
            values.remove(rng.below(values.len() as u64) as usize);
        }
        for bad in values {
            let metadata: Vec<(String, String)> = parsed.metadata.iter().map(|(k, v)| (k.clone(), if k == key { bad.clone() } else { v.clone() })).collect();
            let shown: String = bad.chars().take(24).collect();
            // Damaged: the checksum no longer matches. Forged: the checksum matches, and the
            // value must be refused where it is read (or change nothing where it is not).
            let original = parsed.metadata.iter().find(|(k, _)| k == CHECKSUM_KEY).map_or(String::new(), |(_, v)| v.clone());
            let forged = content_sha256(&metadata.iter().filter(|(k, _)| k != CHECKSUM_KEY).cloned().collect::<Vec<_>>(), &AnyChannels::sort(same_channels().into()));
            // Through the exr crate, else (a text too long for it) spliced into the header.
            let rewrite = |forge: bool| {
                write(&parsed, same_channels(), &metadata, &[], forge)
                    .or_else(|| splice_text(&bytes, key, &bad, if forge { &forged } else { &original }, chunk_count(path)?))
            };
            if let Some(b) = rewrite(false) {
                out.push(Mutant { label: format!("pathlab:{key} = `{shown}` (damaged)"), bytes: b, expect: Expect::Refuse });
            }
            if !legitimately_different(key, &bad) {
                if let Some(b) = rewrite(true) {
                    out.push(Mutant { label: format!("pathlab:{key} = `{shown}` (forged)"), bytes: b, expect: Expect::RefuseOrSame });
                }
            }
        }
        let without: Vec<(String, String)> = parsed.metadata.iter().filter(|(k, _)| k != key).cloned().collect();
        // Without a recorded display transform, a reference is shown in sRGB: valid, different.
        let optional = ["display", "exposure"].contains(&key.as_str());
        if let Some(b) = Some(write(&parsed, same_channels(), &without, &[], true).ok_or_else(|| unwritable(path, "a rewrite"))?).filter(|_| !optional) {
            out.push(Mutant { label: format!("pathlab:{key} removed (forged)"), bytes: b, expect: Expect::RefuseOrSame });
        }
        let dup = [(format!("pathlab:{key}"), "string".to_string(), format!("{value}0").into_bytes())];
        let b = chunk_count(path).and_then(|chunks| splice(&bytes, &[], &dup, chunks));
        out.push(Mutant { label: format!("pathlab:{key} twice"), bytes: b.ok_or_else(|| unwritable(path, "a duplicate"))?, expect: Expect::Refuse });
        let typed = [(key.clone(), AttributeValue::I32(7))];
        if let Some(b) = Some(write(&parsed, same_channels(), &without, &typed, true).ok_or_else(|| unwritable(path, "a rewrite"))?) {
            out.push(Mutant { label: format!("pathlab:{key} as an integer attribute (forged)"), bytes: b, expect: Expect::Refuse });
        }
    }
    // Channels: one removed, one added, one of another type.
    let picks: Vec<usize> = (0..plan.channels).map(|_| rng.below(parsed.channels.len() as u64) as usize).collect();
    for (i, c) in parsed.channels.iter().enumerate().filter(|(i, _)| picks.contains(i)) {
        let name = c.name.to_string();
        let mut removed = same_channels();
        removed.remove(i);
        let mut retyped = same_channels();
        retyped[i].sample_data = match &c.sample_data {
            FlatSamples::U32(v) => FlatSamples::F32(v.iter().map(|&x| x as f32).collect()),
            other => FlatSamples::U32(other.values_as_f32().map(|x| x.max(0.0) as u32).collect()),
        };
        for (what, channels) in [("removed", removed), ("of another sample type", retyped)] {
            for forge in [false, true] {
                if let Some(b) = Some(write(&parsed, channels.clone(), &parsed.metadata, &[], forge).ok_or_else(|| unwritable(path, "a rewrite"))?) {
                    out.push(Mutant { label: format!("channel {name} {what} ({})", if forge { "forged" } else { "damaged" }), bytes: b, expect: Expect::Refuse });
                }
            }
        }
    }
    let mut extra = same_channels();
    let n = parsed.size.0 * parsed.size.1;
    extra.push(AnyChannel::new("junk", FlatSamples::F32(vec![0.5; n])));
    for forge in [false, true] {
        if let Some(b) = Some(write(&parsed, extra.clone(), &parsed.metadata, &[], forge).ok_or_else(|| unwritable(path, "a rewrite"))?) {
            // A forged image may carry channels nothing reads; accumulator files may not.
            let expect = if forge { Expect::RefuseOrSame } else { Expect::Refuse };
            out.push(Mutant { label: format!("extra channel junk ({})", if forge { "forged" } else { "damaged" }), bytes: b, expect });
        }
    }
    // Impossible values in float channels: NaN, infinities, negatives.
    let picks: Vec<usize> = (0..plan.channels).map(|_| rng.below(parsed.channels.len() as u64) as usize).collect();
    for (i, c) in parsed.channels.iter().enumerate().filter(|(i, _)| picks.contains(i)) {
        let FlatSamples::F32(values) = &c.sample_data else { continue };
        let name = c.name.to_string();
        // Error terms of compensated sums may be negative; sums, radiance and variances may not.
        let negative_is_wrong = !name.contains("_err");
        let at = rng.below(values.len() as u64) as usize;
        let mut bad = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
        if negative_is_wrong {
            bad.push(-1.0);
        }
        for x in bad {
            let mut channels = same_channels();
            if let FlatSamples::F32(v) = &mut channels[i].sample_data {
                v[at] = x;
            }
            for forge in [false, true] {
                if let Some(b) = Some(write(&parsed, channels.clone(), &parsed.metadata, &[], forge).ok_or_else(|| unwritable(path, "a rewrite"))?) {
                    out.push(Mutant {
                        label: format!("{name}[{at}] = {x} ({})", if forge { "forged" } else { "damaged" }),
                        bytes: b,
                        expect: Expect::Refuse,
                    });
                }
            }
        }
    }
    // Sample ranges past 2^32 and past 2^64 (accumulator files).
    if parsed.metadata.iter().any(|(k, v)| k == "kind" && v == "accumulator") {
        for (first, spp) in [("18446744073709551615", None), ("4294967295", Some("2")), ("4294967294", None)] {
            let metadata: Vec<(String, String)> = parsed
                .metadata
                .iter()
                .map(|(k, v)| match k.as_str() {
                    "first_sample" => (k.clone(), first.to_string()),
                    "spp" => (k.clone(), spp.map_or(v.clone(), String::from)),
                    _ => (k.clone(), v.clone()),
                })
                .collect();
            if let Some(b) = Some(write(&parsed, same_channels(), &metadata, &[], true).ok_or_else(|| unwritable(path, "a rewrite"))?) {
                out.push(Mutant { label: format!("first_sample {first}, spp {} (forged)", spp.unwrap_or("as before")), bytes: b, expect: Expect::Refuse });
            }
        }
    }
    Ok(out)
}

/// `path` with the pathlab attributes `changes` set (a new key is added, an empty value removes
/// it) and its checksum recomputed: a file as a careless writer would leave it.
pub fn rewritten(path: &Path, changes: &[(&str, &str)]) -> Result<Vec<u8>, OutputError> {
    let parsed = parse(path)?;
    let mut metadata = parsed.metadata.clone();
    for (key, value) in changes {
        metadata.retain(|(k, _)| k != key);
        if !value.is_empty() {
            metadata.push((key.to_string(), value.to_string()));
        }
    }
    let fail = || OutputError::Encode { path: path.to_path_buf(), message: "cannot write the mutant".into() };
    if let Some(b) = write(&parsed, parsed.channels.clone(), &metadata, &[], true) {
        return Ok(b);
    }
    // A text too long for the exr crate: spliced into the header as written (one change).
    let [(key, value)] = changes else { return Err(fail()) };
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io { path: path.to_path_buf(), source })?;
    let checksum = content_sha256(&metadata.iter().filter(|(k, _)| k != CHECKSUM_KEY).cloned().collect::<Vec<_>>(), &AnyChannels::sort(parsed.channels.clone().into()));
    splice_text(&bytes, key, value, &checksum, chunk_count(path).ok_or_else(fail)?).ok_or_else(fail)
}

/// `path` with value `index` of float channel `channel` set to `x`, checksum recomputed.
pub fn with_value(path: &Path, channel: &str, index: usize, x: f32) -> Result<Vec<u8>, OutputError> {
    let parsed = parse(path)?;
    let mut channels = parsed.channels.clone();
    for c in &mut channels {
        if c.name == Text::from(channel) {
            if let FlatSamples::F32(v) = &mut c.sample_data {
                v[index] = x;
            }
        }
    }
    write(&parsed, channels, &parsed.metadata, &[], true).ok_or_else(|| OutputError::Encode { path: path.to_path_buf(), message: "cannot write the mutant".into() })
}

/// `path` with a second `pathlab:KEY` of `value` in its header, checksum recomputed.
pub fn duplicated(path: &Path, key: &str, value: &str) -> Result<Vec<u8>, OutputError> {
    let fail = || OutputError::Encode { path: path.to_path_buf(), message: "cannot write the mutant".into() };
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io { path: path.to_path_buf(), source })?;
    let append = [(format!("pathlab:{key}"), "string".to_string(), value.as_bytes().to_vec())];
    splice(&bytes, &[], &append, chunk_count(path).ok_or_else(fail)?).ok_or_else(fail)
}
