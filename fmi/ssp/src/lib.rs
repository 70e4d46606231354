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
mod fmu_values;
mod model;
mod names;
mod number;
mod prescan;
mod read;
mod schema;
mod write;

pub use archive::{MAX_SSD_BYTES, SSD_ENTRY, extract_ssp, read_ssd_from_ssp, read_ssp, write_ssp, write_ssp_archive};
pub use bindings::{SourceReader, parse_ssv, ssv_xml};
pub use error::SspError;
pub use fmu_values::{Enumerations, fmu_parameter};
pub use model::{
    ComponentDesc, Connection, Connector, ConnectorKind, ConnectorType, Linear, MasterSettings, Order, ParamValue,
    Parameter, SystemDescription,
};
pub use names::{ANNOTATION_TYPE, NS_MASTER, NS_SSB, NS_SSC, NS_SSD, NS_SSM, NS_SSV};
pub use prescan::MAX_DEPTH;
