//! Checking one entry name: the relative path it may extract to.

use std::path::{Component, PathBuf};

/// Check one entry name; return the relative path it extracts to.
///
/// Refused: NUL bytes, absolute paths (`/x`, `\x`, `C:x`) and any `..`
/// component. Backslashes count as separators (some Windows tools write
/// them); empty and `.` components are dropped.
pub fn safe_entry_path(name: &str) -> Result<PathBuf, &'static str> {
    if name.contains('\0') {
        return Err("NUL byte in the name");
    }
    let unified = name.replace('\\', "/");
    if unified.starts_with('/') {
        return Err("absolute path");
    }
    let b = unified.as_bytes();
    if b.len() >= 2 && b[0].is_ascii_alphabetic() && b[1] == b':' {
        return Err("absolute path with a drive letter");
    }
    let mut out = PathBuf::new();
    for part in unified.split('/') {
        match part {
            "" | "." => {}
            ".." => return Err("'..' component escapes the extraction directory"),
            p => out.push(p),
        }
    }
    // Belt and braces: the result must be a plain relative path.
    if out.components().any(|c| !matches!(c, Component::Normal(_))) {
        return Err("not a plain relative path");
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entry_names_are_checked() {
        assert_eq!(safe_entry_path("a/b/c.txt").unwrap(), PathBuf::from("a/b/c.txt"));
        assert_eq!(safe_entry_path("./a//b").unwrap(), PathBuf::from("a/b"));
        assert_eq!(safe_entry_path("a\\b").unwrap(), PathBuf::from("a/b"));
        assert!(safe_entry_path("../evil").is_err());
        assert!(safe_entry_path("a/../../evil").is_err());
        assert!(safe_entry_path("a\\..\\evil").is_err());
        assert!(safe_entry_path("/etc/passwd").is_err());
        assert!(safe_entry_path("\\windows\\x").is_err());
        assert!(safe_entry_path("C:evil").is_err());
        assert!(safe_entry_path("a\0b").is_err());
        // A name that merely contains dots is fine.
        assert!(safe_entry_path("a/..b/c..").is_ok());
    }
}
