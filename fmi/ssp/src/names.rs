//! The namespaces of SSP 1.0 and the name of this master's annotation.

/// Namespace of `ssd:` elements (system structure).
pub const NS_SSD: &str = "http://ssp-standard.org/SSP1/SystemStructureDescription";
/// Namespace of `ssc:` elements (common types, annotations, transformations).
pub const NS_SSC: &str = "http://ssp-standard.org/SSP1/SystemStructureCommon";
/// Namespace of `ssv:` elements (parameter values).
pub const NS_SSV: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";
/// Namespace of `ssm:` elements (parameter mappings: recognised, not supported).
pub const NS_SSM: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterMapping";
/// Namespace of `ssb:` elements (signal dictionaries: recognised, not supported).
pub const NS_SSB: &str = "http://ssp-standard.org/SSP1/SystemStructureSignalDictionary";
/// Type of this master's annotation (communication step, order, sequence).
pub const ANNOTATION_TYPE: &str = "org.chatter-fmu.master";
/// Namespace of the `Settings` element inside that annotation.
pub const NS_MASTER: &str = "urn:chatter-fmu:master:1";
