//! Where bytes come from: data URIs (base64 or percent-encoded), files relative to the
//! glTF file, the `.glb` BIN chunk. Written here rather than taken from gltf's `import`
//! feature, whose URI reader panics on some percent-encodings and names no buffer.

use std::path::{Path, PathBuf};

/// The bytes a URI names: a `data:` URI decoded, or a file relative to `base` (or a
/// `file:` URI). `Err` is a sentence saying why not.
pub(crate) fn read_uri(base: Option<&Path>, uri: &str) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((meta, data)) = rest.split_once(',') else {
            return Err("a data URI without a ',' before its data".to_owned());
        };
        return if meta.ends_with(";base64") {
            base64(data).map_err(|e| format!("a data URI whose base64 is malformed: {e}"))
        } else {
            Ok(percent_decode(data))
        };
    }
    let path = if let Some(rest) = uri.strip_prefix("file://") {
        PathBuf::from(bytes_to_path(percent_decode(rest))?)
    } else if let Some(rest) = uri.strip_prefix("file:") {
        PathBuf::from(bytes_to_path(percent_decode(rest))?)
    } else if has_scheme(uri) {
        let scheme = uri.split(':').next().unwrap_or_default();
        return Err(format!(
            "the URI scheme {scheme:?} is not supported (data URIs and relative file paths are)"
        ));
    } else {
        let relative = bytes_to_path(percent_decode(uri))?;
        let Some(base) = base else {
            return Err(format!(
                "it names the external file {relative:?}, but the glTF was given as bytes with no \
                 base directory"
            ));
        };
        base.join(relative)
    };
    std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// Whether `uri` starts with an RFC 3986 scheme (`letter *(letter / digit / + - .) :`),
/// and so is not a relative path. A Windows drive letter (`C:`) counts as a path.
fn has_scheme(uri: &str) -> bool {
    let Some((scheme, _)) = uri.split_once(':') else {
        return false;
    };
    scheme.len() > 1
        && scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

fn bytes_to_path(bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|_| "a URI whose percent-encoding is not UTF-8".to_owned())
}

/// `%XX` sequences decoded; a `%` not followed by two hex digits is kept as it is.
fn percent_decode(s: &str) -> Vec<u8> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let (Some(h), Some(l)) = (
                b.get(i + 1).and_then(|&c| hex(c)),
                b.get(i + 2).and_then(|&c| hex(c)),
            )
        {
            out.push(h << 4 | l);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    out
}

fn hex(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'a'..=b'f' => Some(c - b'a' + 10),
        b'A'..=b'F' => Some(c - b'A' + 10),
        _ => None,
    }
}

/// Standard (RFC 4648) base64, with or without `=` padding; ASCII whitespace is skipped and
/// the URL-safe `-` and `_` are accepted.
pub(crate) fn base64(s: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    let mut padding = 0usize;
    for (at, c) in s.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => {
                padding += 1;
                continue;
            }
            b' ' | b'\t' | b'\r' | b'\n' => continue,
            _ => return Err(format!("byte {c:#04x} at offset {at} is not base64")),
        };
        if padding > 0 {
            return Err(format!("data after '=' padding at offset {at}"));
        }
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("a final group of one character (truncated base64)".to_owned());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        // RFC 4648 §10.
        for (enc, dec) in [
            ("", ""),
            ("Zg==", "f"),
            ("Zm8=", "fo"),
            ("Zm9v", "foo"),
            ("Zm9vYg==", "foob"),
            ("Zm9vYmE=", "fooba"),
            ("Zm9vYmFy", "foobar"),
            ("Zm9vYmE", "fooba"),
        ] {
            assert_eq!(base64(enc).unwrap(), dec.as_bytes(), "{enc}");
        }
        assert!(base64("Zm9v!").is_err());
        assert!(base64("Z").is_err());
        assert!(base64("Zg==Zg").is_err());
    }

    #[test]
    fn percent_decoding_and_schemes() {
        assert_eq!(percent_decode("a%20b%zz%4"), b"a b%zz%4");
        assert_eq!(percent_decode("%C3%A9"), "é".as_bytes());
        assert!(has_scheme("http://x"));
        assert!(!has_scheme("C:/models/a.bin"));
        assert!(!has_scheme("models/a.bin"));
        assert_eq!(read_uri(None, "data:,a%20b").unwrap(), b"a b");
        assert!(read_uri(None, "http://example.invalid/a.bin").is_err());
        assert!(
            read_uri(None, "a.bin")
                .unwrap_err()
                .contains("no base directory")
        );
        assert!(read_uri(None, "%FF.bin").is_err());
    }
}
