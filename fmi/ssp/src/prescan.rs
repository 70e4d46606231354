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

/// Most attributes on one element (SSP 1.0 elements have at most a dozen, plus namespace
/// declarations). The pre-scan counts them as it streams and checks their names for duplicates;
/// the serde pass after it checks every attribute against the ones before it on the same element,
/// which made a 4 MB SSD with 300 000 attributes on one element run past 60 s (parse time grew
/// with the square of the attribute count).
pub const MAX_ATTRIBUTES: usize = 64;

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
        check_attributes(e, file, line)?;
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

/// At most [`MAX_ATTRIBUTES`] attributes on `e`, each name once (linear in the document: the
/// duplicate check compares within this bounded set only).
fn check_attributes(
    e: &quick_xml::events::BytesStart<'_>,
    file: &str,
    line: impl Fn() -> usize,
) -> Result<(), SspError> {
    let mut names: Vec<&[u8]> = Vec::new();
    for a in e.attributes().with_checks(false) {
        let a =
            a.map_err(|err| SspError::Xml { file: file.to_string(), message: format!("line {}: {err}", line()) })?;
        let name = a.key.into_inner();
        if names.len() == MAX_ATTRIBUTES {
            return Err(SspError::Invalid {
                file: file.to_string(),
                message: format!(
                    "line {}: element <{}> has more than {MAX_ATTRIBUTES} attributes (an SSP element has about a dozen)",
                    line(),
                    String::from_utf8_lossy(e.name().as_ref())
                ),
            });
        }
        if names.contains(&name) {
            return Err(SspError::Xml {
                file: file.to_string(),
                message: format!("line {}: attribute '{}' appears twice", line(), String::from_utf8_lossy(name)),
            });
        }
        names.push(name);
    }
    Ok(())
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

    /// Parse time grew with the square of the attribute count (5k/10k/20k/40k attributes:
    /// 0.25/0.94/2.7/12.6 s); 300 000 attributes on one element are now refused at once, and a
    /// document of many elements with a few attributes each reads in linear time.
    #[test]
    fn attributes_are_bounded_per_element_and_checked_in_linear_time() {
        let element = |n: usize| {
            let attrs: String = (0..n).map(|i| format!(" a{i}=\"x\"")).collect();
            format!("{HEAD}<ssd:System name=\"s\"{attrs}/></ssd:SystemStructureDescription>")
        };
        prescan(&element(MAX_ATTRIBUTES - 1), "ok.ssd", SSD_ROOT).unwrap();
        let e = prescan(&element(300_000), "wide.ssd", SSD_ROOT).unwrap_err().to_string();
        assert!(e.contains("has more than 64 attributes"), "{e}");
        let e = crate::SystemDescription::from_xml(&element(300_000), "wide.ssd", None).unwrap_err().to_string();
        assert!(e.contains("has more than 64 attributes"), "{e}");
        let twice = format!("{HEAD}<ssd:System name=\"s\" name=\"t\"/></ssd:SystemStructureDescription>");
        assert!(prescan(&twice, "twice.ssd", SSD_ROOT).unwrap_err().to_string().contains("'name' appears twice"));
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
