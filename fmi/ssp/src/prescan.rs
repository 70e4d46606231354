//! The streaming pre-scan every document passes before serde sees it, and
//! [`deserialize`], the one entry point from XML text to schema types.
//!
//! One pass of quick-xml's namespace-resolving reader, with constant stack
//! use whatever the input, checks that the XML is well-formed, that the root
//! element is the expected one in its SSP namespace, that every element
//! outside `ssc:Annotation` content is in an SSP 1.0 namespace, and that no
//! element is nested deeper than [`crate::MAX_DEPTH`]. The serde types can
//! then rely on a shallow, namespace-checked document (a document 300 000
//! elements deep would otherwise exhaust the stack).

use crate::error::SspError;
use crate::names::{NS_SSB, NS_SSC, NS_SSD, NS_SSM, NS_SSV};
use quick_xml::events::Event;
use quick_xml::name::ResolveResult;

/// Deepest element nesting accepted in an SSD or `.ssv` (an SSD needs about a dozen levels).
pub const MAX_DEPTH: usize = 64;

/// The expected root element of a document.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Root {
    /// Its namespace.
    pub ns: &'static str,
    /// Its local name.
    pub local: &'static str,
    /// How to name it in messages (`ssd:SystemStructureDescription`).
    pub label: &'static str,
}

/// The root of a `SystemStructure.ssd`.
pub(crate) const SSD_ROOT: Root =
    Root { ns: NS_SSD, local: "SystemStructureDescription", label: "ssd:SystemStructureDescription" };
/// The root of an `.ssv` parameter file.
pub(crate) const SSV_ROOT: Root = Root { ns: NS_SSV, local: "ParameterSet", label: "ssv:ParameterSet" };

const SSP_NAMESPACES: [&str; 5] = [NS_SSD, NS_SSC, NS_SSV, NS_SSM, NS_SSB];

/// 1-based line of byte offset `pos` in `text`.
pub(crate) fn line_of(text: &str, pos: usize) -> usize {
    1 + text.as_bytes()[..pos.min(text.len())].iter().filter(|&&b| b == b'\n').count()
}

/// Check `xml` (see the module documentation). XML errors come first: a
/// wrong root element is reported once the whole document has been read.
pub(crate) fn prescan(xml: &str, file: &str, root: Root) -> Result<(), SspError> {
    let mut reader = quick_xml::reader::NsReader::from_str(xml);
    let mut depth = 0usize;
    let mut wrong_root: Option<String> = None;
    let mut seen_root = false;
    // Depth of the `ssc:Annotation` element we are inside (its content is free-form).
    let mut annotation: Option<usize> = None;
    loop {
        let at = reader.buffer_position() as usize;
        let line = || line_of(xml, at);
        let xml_err =
            |message: String| SspError::Xml { file: file.to_string(), message: format!("line {}: {message}", line()) };
        let (ns, event) = reader.read_resolved_event().map_err(|e| xml_err(e.to_string()))?;
        let (e, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                if annotation.is_some_and(|d| depth < d) {
                    annotation = None;
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let local = String::from_utf8_lossy(e.local_name().as_ref()).into_owned();
        let ns = match ns {
            ResolveResult::Bound(n) => String::from_utf8_lossy(n.as_ref()).into_owned(),
            ResolveResult::Unbound => String::new(),
            ResolveResult::Unknown(p) => {
                return Err(xml_err(format!("undeclared namespace prefix '{}'", String::from_utf8_lossy(&p))));
            }
        };
        if depth == 0 {
            if seen_root {
                return Err(xml_err(format!("element <{local}> after the root element")));
            }
            seen_root = true;
            if ns != root.ns || local != root.local {
                wrong_root =
                    Some(format!("root element is {{{ns}}}{local}, expected {} in namespace {}", root.label, root.ns));
            }
        }
        depth += 1;
        if depth > MAX_DEPTH {
            return Err(SspError::TooDeep { file: file.to_string(), line: line(), limit: MAX_DEPTH });
        }
        if wrong_root.is_none() && annotation.is_none() {
            if !SSP_NAMESPACES.contains(&ns.as_str()) {
                return Err(SspError::Invalid {
                    file: file.to_string(),
                    message: format!(
                        "line {}: element {{{ns}}}{local} is not in an SSP 1.0 namespace (only ssc:Annotation content may be)",
                        line()
                    ),
                });
            }
            if ns == NS_SSC && local == "Annotation" && !empty {
                annotation = Some(depth);
            }
        }
        if empty {
            depth -= 1;
        }
    }
    if !seen_root {
        return Err(SspError::Xml { file: file.to_string(), message: "empty document (no root element)".into() });
    }
    match wrong_root {
        Some(message) => Err(SspError::Invalid { file: file.to_string(), message }),
        None => Ok(()),
    }
}

/// Pre-scan `xml` (root `root`), then deserialize it into a schema type.
pub(crate) fn deserialize<T: serde::de::DeserializeOwned>(xml: &str, file: &str, root: Root) -> Result<T, SspError> {
    prescan(xml, file, root)?;
    quick_xml::de::from_str(xml).map_err(|e| SspError::Xml { file: file.to_string(), message: e.to_string() })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = r#"<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0" name="x">"#;

    #[test]
    fn depth_is_limited_without_recursion() {
        let nest = |n: usize| {
            format!("{HEAD}{}{}</ssd:SystemStructureDescription>", "<ssd:System>".repeat(n), "</ssd:System>".repeat(n))
        };
        prescan(&nest(MAX_DEPTH - 1), "ok.ssd", SSD_ROOT).unwrap();
        let e = prescan(&nest(MAX_DEPTH), "deep.ssd", SSD_ROOT).unwrap_err();
        assert!(matches!(e, SspError::TooDeep { limit: MAX_DEPTH, .. }), "{e}");
        // 300 000 levels: a clear error, not a stack overflow.
        let e = prescan(&nest(300_000), "bomb.ssd", SSD_ROOT).unwrap_err();
        assert!(e.to_string().starts_with("bomb.ssd: line 1: elements are nested more than 64 levels deep"), "{e}");
    }

    #[test]
    fn namespaces_are_checked_outside_annotations() {
        let foreign = format!("{HEAD}<x:Foo xmlns:x=\"urn:x\"/></ssd:SystemStructureDescription>");
        let e = prescan(&foreign, "f.ssd", SSD_ROOT).unwrap_err();
        assert!(e.to_string().contains("element {urn:x}Foo is not in an SSP 1.0 namespace"), "{e}");
        let annotated = format!(
            "{HEAD}<ssd:Annotations><ssc:Annotation type=\"t\"><x:Foo xmlns:x=\"urn:x\"><Bar/></x:Foo></ssc:Annotation></ssd:Annotations></ssd:SystemStructureDescription>"
        );
        prescan(&annotated, "a.ssd", SSD_ROOT).unwrap();
        let e = prescan(&format!("{HEAD}<q:System/></ssd:SystemStructureDescription>"), "u.ssd", SSD_ROOT).unwrap_err();
        assert!(e.to_string().contains("undeclared namespace prefix 'q'"), "{e}");
        let e = prescan("", "e.ssd", SSD_ROOT).unwrap_err();
        assert!(e.to_string().contains("empty document"), "{e}");
    }
}
