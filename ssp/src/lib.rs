//! # ssp — SSP 1.0 system structure descriptions
//!
//! Read and write `SystemStructure.ssd` (and `.ssv` parameter files) of the
//! System Structure and Parameterization standard 1.0, and `.ssp` archives.
//!
//! * [`SystemDescription`] and the types around it ([`ComponentDesc`],
//!   [`Connector`], [`Connection`], [`Parameter`], [`ParamValue`],
//!   [`MasterSettings`], [`Order`]) are the model a master works with.
//! * [`SystemDescription::from_xml`] reads an SSD: a streaming pre-scan
//!   (well-formedness, namespaces, nesting at most [`MAX_DEPTH`] deep), then
//!   quick-xml's serde deserializer into the schema types, then checked
//!   conversion; errors name the file and what is wrong.
//!   [`SystemDescription::to_xml`] writes one with quick-xml's serializer.
//! * Parameter bindings ([`parse_ssv`], [`SourceReader`]): inline or in
//!   `.ssv` files, with `prefix`; one value per parameter and binding.
//! * Archives ([`read_ssp`], [`extract_ssp`], [`write_ssp_archive`]) go
//!   through `fmi-archive` (safe extraction, size caps, deterministic zip).
//!
//! This master's communication step, stepping order and Gauss–Seidel
//! sequence, which SSP 1.0 has no attribute for, travel as an annotation of
//! `ssd:DefaultExperiment` of type [`ANNOTATION_TYPE`]:
//!
//! ```xml
//! <ssc:Annotation type="org.chatter-fmu.master">
//!   <master:Settings xmlns:master="urn:chatter-fmu:master:1" stepSize="1e-5" order="gauss-seidel" sequence="controller plant"/>
//! </ssc:Annotation>
//! ```

mod archive;
mod bindings;
mod error;
mod model;
mod prescan;
mod read;
mod schema;
mod write;

pub use archive::{MAX_SSD_BYTES, SSD_ENTRY, extract_ssp, read_ssd_from_ssp, read_ssp, write_ssp, write_ssp_archive};
pub use bindings::{SourceReader, parse_ssv};
pub use error::SspError;
pub use model::{
    ComponentDesc, Connection, Connector, ConnectorKind, ConnectorType, Linear, MasterSettings, Order, ParamValue,
    Parameter, SystemDescription,
};

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
/// Deepest element nesting accepted in an SSD or `.ssv` (an SSD needs about a dozen levels).
pub const MAX_DEPTH: usize = 64;

impl SystemDescription {
    /// Parse an SSD document. `file` names it in errors; `read_source`
    /// reads `source=` files of parameter bindings relative to the SSD (None:
    /// such references are an error).
    pub fn from_xml(xml: &str, file: &str, read_source: Option<SourceReader<'_>>) -> Result<Self, SspError> {
        read::parse_ssd(xml, file, read_source)
    }

    /// Render as a standard `SystemStructure.ssd` (SSP 1.0, UTF-8, with XML declaration).
    pub fn to_xml(&self) -> Result<String, SspError> {
        write::to_xml(self)
    }
}
