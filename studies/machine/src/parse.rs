//! Reading each table of a machine file ([`crate::machine`]): the quantity fields with their
//! dimensions, physical ranges and likely unit slips, and the checks between fields.

use crate::frf::MeasuredFrf;
use crate::machine::{
    Actuator, Axis, ControllerChoice, Law, Machine, Material, Milling, Mode, Operation, Tool, VERSION,
};
use crate::read::{Field, MachineError, Node};
use crate::units::{self, FORCE, FREQUENCY, LENGTH, MASS, ONE, PRESSURE, STIFFNESS};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const FREQ: Field = Field {
    what: "a natural frequency",
    dim: FREQUENCY,
    si_unit: "rad/s",
    report: ("Hz", 1.0 / (2.0 * PI)),
    range: (2.0 * PI * 1.0, 2.0 * PI * 5e4),
    slips: &[(2.0 * PI, "Hz")],
    example: "\"600 Hz\"",
};
const DAMPING: Field = Field {
    what: "a damping ratio",
    dim: ONE,
    si_unit: "(ratio)",
    report: ("", 1.0),
    range: (1e-4, 0.5),
    slips: &[(0.01, "%")],
    example: "0.03 or \"3 %\"",
};
const STIFF: Field = Field {
    what: "a modal stiffness",
    dim: STIFFNESS,
    si_unit: "N/m",
    report: ("N/m", 1.0),
    range: (1e4, 1e11),
    slips: &[(1e3, "N/mm"), (1e6, "N/µm")],
    example: "\"2e7 N/m\" or \"20 N/µm\"",
};
const MODAL_MASS: Field = Field {
    what: "a modal mass",
    dim: MASS,
    si_unit: "kg",
    report: ("kg", 1.0),
    range: (1e-4, 1e5),
    slips: &[(1e-3, "g")],
    example: "\"0.8 kg\"",
};
const DIAMETER: Field = Field {
    what: "the tool diameter",
    dim: LENGTH,
    si_unit: "m",
    report: ("mm", 1e3),
    range: (1e-4, 1.0),
    slips: &[(1e-3, "mm")],
    example: "\"12 mm\"",
};
const ANGLE: Field = Field {
    what: "an angle",
    dim: ONE,
    si_unit: "rad",
    report: ("deg", 180.0 / PI),
    range: (-2.0 * PI, 4.0 * PI),
    slips: &[(PI / 180.0, "deg")],
    example: "\"30 deg\"",
};
const KT: Field = Field {
    what: "K_t",
    dim: PRESSURE,
    si_unit: "N/m^2",
    report: ("N/mm^2", 1e-6),
    range: (5e7, 2e10),
    slips: &[(1e6, "N/mm^2")],
    example: "\"800 N/mm^2\"",
};
const KR: Field = Field { what: "K_r", range: (0.0, 2e10), ..KT };
const EDGE: Field = Field {
    what: "an edge coefficient",
    dim: STIFFNESS,
    si_unit: "N/m",
    report: ("N/mm", 1e-3),
    range: (0.0, 1e6),
    slips: &[(1e3, "N/mm")],
    example: "\"20 N/mm\"",
};
const FEED: Field = Field {
    what: "the feed per tooth",
    dim: LENGTH,
    si_unit: "m",
    report: ("mm", 1e3),
    range: (1e-7, 2e-3),
    slips: &[(1e-3, "mm"), (1e-6, "µm")],
    example: "\"0.05 mm\"",
};
const DEPTH: Field = Field {
    what: "the axial depth",
    dim: LENGTH,
    si_unit: "m",
    report: ("mm", 1e3),
    range: (0.0, 0.2),
    slips: &[(1e-3, "mm")],
    example: "\"2 mm\"",
};
const SPEED: Field = Field {
    what: "a spindle speed",
    dim: FREQUENCY,
    si_unit: "rad/s",
    report: ("rpm", 60.0 / (2.0 * PI)),
    range: (2.0 * PI / 60.0, 2.0 * PI / 60.0 * 3e5),
    slips: &[(2.0 * PI / 60.0, "rpm")],
    example: "\"10000 rpm\"",
};
const FORCE_LIMIT: Field = Field {
    what: "a force limit",
    dim: FORCE,
    si_unit: "N",
    report: ("N", 1.0),
    range: (1e-3, 1e6),
    slips: &[],
    example: "\"27 N\"",
};

impl Machine {
    /// Read a machine file.
    pub fn from_file(path: &Path) -> Result<Machine, MachineError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| MachineError {
            file: file.clone(),
            field: String::new(),
            message: format!("cannot read: {e}"),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| MachineError {
            file: file.clone(),
            field: String::new(),
            message: format!("not valid TOML: {}", e.message().trim()),
        })?;
        let mut m = Machine::from_table_in(&table, &file, base)?;
        if let Some(c) = &mut m.controller
            && let Some(p) = &mut c.parameters
            && p.is_relative()
        {
            *p = path.parent().unwrap_or(Path::new(".")).join(&*p);
        }
        Ok(m)
    }

    /// Read a machine from TOML text (`file` names it in messages).
    pub fn from_toml(text: &str, file: &str) -> Result<Machine, MachineError> {
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| MachineError {
            file: file.to_string(),
            field: String::new(),
            message: format!("not valid TOML: {}", e.message().trim()),
        })?;
        Machine::from_table(&table, file)
    }

    /// Read a machine from a parsed TOML table (measured FRF files relative to the current
    /// folder).
    pub fn from_table(table: &toml::Table, file: &str) -> Result<Machine, MachineError> {
        Machine::from_table_in(table, file, Path::new("."))
    }

    /// Read a machine from a parsed TOML table, measured FRF files relative to `base`.
    pub fn from_table_in(table: &toml::Table, file: &str, base: &Path) -> Result<Machine, MachineError> {
        let root = Node::root(file, table);
        root.finish(&["version", "name", "tool", "structure", "material", "operation", "actuator", "controller"])?;
        let version =
            root.integer("version", (0, i64::MAX))?.ok_or_else(|| root.missing("version", "the schema version (1)"))?;
        if version != VERSION {
            return Err(root
                .err("version", format!("schema version {version} is not known: this tool reads version {VERSION}")));
        }
        let name = root.string("name")?.unwrap_or_else(|| "machine".into());
        let mut warnings = Vec::new();
        let tool = read_tool(&root, &mut warnings)?;
        let (modes, frf) = read_structure(&root, base)?;
        let material = read_material(&root)?;
        let peaks: Vec<f64> = if modes.is_empty() {
            frf.as_ref().map(MeasuredFrf::peak_hz).into_iter().collect()
        } else {
            modes.iter().map(|m| m.frequency_hz).collect()
        };
        let operation = read_operation(&root, &tool, &peaks)?;
        let actuator = read_actuator(&root)?;
        let controller = read_controller(&root)?;
        if controller.as_ref().is_some_and(|c| c.structure != "off") && actuator.is_none() {
            return Err(root.err("controller", "a controller needs an [actuator] table (its axis and force limit)"));
        }
        if modes.is_empty() && controller.is_some() {
            return Err(root.err(
                "controller",
                "a controller needs the structure's modes (fit the measured FRFs: chatter frf fit ... --machine FILE)",
            ));
        }
        Ok(Machine { name, tool, modes, frf, material, operation, actuator, controller, warnings })
    }
}

pub(crate) fn read_tool(root: &Node<'_>, warnings: &mut Vec<String>) -> Result<Tool, MachineError> {
    let t = root.table("tool")?.ok_or_else(|| root.missing("tool", "the cutter ([tool] with teeth and diameter)"))?;
    t.finish(&["teeth", "diameter", "pitch", "helix"])?;
    let teeth = t.integer("teeth", (1, 100))?.ok_or_else(|| t.missing("teeth", "the number of teeth"))? as u32;
    let diameter =
        t.quantity("diameter", &DIAMETER)?.ok_or_else(|| t.missing("diameter", "the tool diameter, e.g. \"12 mm\""))?;
    let pitch = match t.get("pitch") {
        None => None,
        Some(toml::Value::Array(items)) => {
            if items.len() != teeth as usize {
                return Err(
                    t.err("pitch", format!("{} angles for {teeth} teeth: give one angle per tooth", items.len()))
                );
            }
            let angles = items.iter().map(|v| t.quantity_value("pitch", v, &ANGLE)).collect::<Result<Vec<_>, _>>()?;
            if angles.windows(2).any(|w| w[1] <= w[0])
                || angles.last().zip(angles.first()).is_some_and(|(l, f)| l - f >= 2.0 * PI)
            {
                return Err(t.err("pitch", "the tooth angles must increase within one turn"));
            }
            let uniform = angles
                .iter()
                .enumerate()
                .all(|(j, a)| (a - angles[0] - 2.0 * PI * j as f64 / teeth as f64).abs() < 1e-9);
            (!uniform).then_some(angles)
        }
        Some(other) => return Err(t.err("pitch", format!("expected a list of angles, found a {}", other.type_str()))),
    };
    let helix = t.quantity("helix", &Field { what: "the helix angle", range: (0.0, 1.2), ..ANGLE })?.unwrap_or(0.0);
    if helix != 0.0 {
        warnings.push(format!(
            "helix = {:.1} deg is not modelled: the lobes and the process FMU treat the cutter as straight-fluted",
            helix.to_degrees()
        ));
    }
    Ok(Tool { teeth, diameter, pitch, helix })
}

fn read_mode(n: &Node<'_>, label: String, shape: Option<[f64; 2]>) -> Result<Mode, MachineError> {
    n.finish(&["frequency", "damping", "stiffness", "mass", "shape"])?;
    let omega = n
        .quantity("frequency", &FREQ)?
        .ok_or_else(|| n.missing("frequency", "the natural frequency, e.g. \"600 Hz\""))?;
    let damping =
        n.quantity("damping", &DAMPING)?.ok_or_else(|| n.missing("damping", "the damping ratio, e.g. 0.03"))?;
    let shape = match shape {
        Some(s) => s,
        None => {
            let v = match n.get("shape") {
                Some(toml::Value::Array(a)) if a.len() == 2 => {
                    let x = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
                    match (x(&a[0]), x(&a[1])) {
                        (Some(a), Some(b)) => [a, b],
                        _ => return Err(n.err("shape", "expected two numbers [sx, sy]")),
                    }
                }
                Some(_) => {
                    return Err(n.err("shape", "expected two numbers [sx, sy] (the mode's direction at the tool)"));
                }
                None => return Err(n.missing("shape", "the mode's direction [sx, sy] (or give the mode under x or y)")),
            };
            let len = v[0].hypot(v[1]);
            if !(len.is_finite() && len > 0.0) {
                return Err(n.err("shape", "the shape must be a nonzero finite vector"));
            }
            [v[0] / len, v[1] / len]
        }
    };
    let stiffness = match (n.quantity("stiffness", &STIFF)?, n.quantity("mass", &MODAL_MASS)?) {
        (Some(k), None) => k,
        (None, Some(m)) => {
            let k = m * omega * omega;
            if !(STIFF.range.0..=STIFF.range.1).contains(&k) {
                return Err(n.err(
                    "mass",
                    format!(
                        "the stiffness m ω² = {} N/m is outside [1e4, 1e11] N/m: check the mass and the frequency",
                        units::short(k)
                    ),
                ));
            }
            k
        }
        (Some(_), Some(_)) => return Err(n.err("mass", "give either stiffness or mass, not both")),
        (None, None) => return Err(n.missing("stiffness", "the modal stiffness (e.g. \"2e7 N/m\") or the modal mass")),
    };
    Ok(Mode { label, frequency_hz: omega / (2.0 * PI), damping, stiffness, shape })
}

pub(crate) fn read_structure(root: &Node<'_>, base: &Path) -> Result<(Vec<Mode>, Option<MeasuredFrf>), MachineError> {
    let s = root.table("structure")?.ok_or_else(|| {
        root.missing("structure", "the modes ([structure] with x = [...] and y = [...]) or measured FRFs (frf = [...])")
    })?;
    s.finish(&["x", "y", "modes", "frf"])?;
    let mut modes = Vec::new();
    for (key, shape) in [("x", Some(Axis::X.unit())), ("y", Some(Axis::Y.unit())), ("modes", None)] {
        for (i, n) in s.tables(key)?.iter().enumerate() {
            modes.push(read_mode(n, format!("{key}[{i}]"), shape)?);
        }
    }
    let files: Vec<String> = match s.get("frf") {
        None => Vec::new(),
        Some(toml::Value::String(f)) => vec![f.clone()],
        Some(toml::Value::Array(a)) if !a.is_empty() && a.iter().all(toml::Value::is_str) => {
            a.iter().filter_map(|v| v.as_str().map(String::from)).collect()
        }
        Some(_) => {
            return Err(s.err(
                "frf",
                "a file name or a list of them (CSV or UFF 58), e.g. frf = [\"tap_xx.csv\", \"tap_yy.csv\"]",
            ));
        }
    };
    let frf = if files.is_empty() {
        None
    } else {
        let paths: Vec<PathBuf> =
            files.iter().map(|f| if Path::new(f).is_relative() { base.join(f) } else { PathBuf::from(f) }).collect();
        Some(MeasuredFrf::read(&paths).map_err(|e| s.err("frf", e.to_string()))?)
    };
    if modes.is_empty() && frf.is_none() {
        return Err(s.err("", "no modes: give at least one under x, y or modes, or measured FRFs under frf"));
    }
    Ok((modes, frf))
}

pub(crate) fn read_material(root: &Node<'_>) -> Result<Material, MachineError> {
    let m = root
        .table("material")?
        .ok_or_else(|| root.missing("material", "the cutting coefficients ([material] with kt and kr)"))?;
    m.finish(&["law", "x_f", "kt", "kr", "kr_ratio", "kte", "kre"])?;
    let law = match m.choice("law", &["linear", "power"])?.as_deref() {
        None | Some("linear") => Law::Linear,
        _ => {
            let x_f = match m.get("x_f") {
                Some(v) => v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).filter(|x| *x > 0.0 && *x <= 1.0),
                None => return Err(m.missing("x_f", "the exponent x_F of the power law (0 < x_F <= 1)")),
            };
            Law::Power { x_f: x_f.ok_or_else(|| m.err("x_f", "the exponent must be a number in (0, 1]"))? }
        }
    };
    let (kt, kr) = match law {
        Law::Linear => {
            let kt = m
                .quantity("kt", &KT)?
                .ok_or_else(|| m.missing("kt", "the tangential cutting coefficient, e.g. \"800 N/mm^2\""))?;
            let kr = match (m.quantity("kr", &KR)?, m.get("kr_ratio")) {
                (Some(kr), None) => kr,
                (None, Some(v)) => {
                    kt * v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .filter(|r| (0.0..=3.0).contains(r))
                        .ok_or_else(|| m.err("kr_ratio", "K_r/K_t must be a number in [0, 3]"))?
                }
                (Some(_), Some(_)) => return Err(m.err("kr_ratio", "give either kr or kr_ratio, not both")),
                (None, None) => {
                    return Err(m.missing("kr", "the radial coefficient (kr = \"240 N/mm^2\" or kr_ratio = 0.3)"));
                }
            };
            (kt, kr)
        }
        Law::Power { x_f } => {
            // K in N/m^(1+x_F): a dimension that depends on x_F, so SI numbers only
            let num = |key: &str| -> Result<Option<f64>, MachineError> {
                match m.get(key) {
                    None => Ok(None),
                    Some(v) => v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .filter(|x| x.is_finite() && *x >= 0.0)
                        .map(Some)
                        .ok_or_else(|| {
                            m.err(
                                key,
                                format!("the power law takes K in N/m^(1+x_F) = N/m^{} as an SI number", 1.0 + x_f),
                            )
                        }),
                }
            };
            let kt = num("kt")?.ok_or_else(|| m.missing("kt", "K_t in N/m^(1+x_F)"))?;
            let kr = match (num("kr")?, m.get("kr_ratio")) {
                (Some(kr), _) => kr,
                (None, Some(v)) => kt * v.as_float().unwrap_or(f64::NAN),
                (None, None) => return Err(m.missing("kr", "K_r in N/m^(1+x_F) (or kr_ratio)")),
            };
            if !(kt > 0.0 && kr.is_finite()) {
                return Err(m.err("kt", "K_t must be positive"));
            }
            (kt, kr)
        }
    };
    let kte = m.quantity("kte", &EDGE)?.unwrap_or(0.0);
    let kre = m.quantity("kre", &EDGE)?.unwrap_or(0.0);
    if law != Law::Linear && (kte != 0.0 || kre != 0.0) {
        return Err(m.err("kte", "edge coefficients belong to the linear law"));
    }
    Ok(Material { law, kt, kr, kte, kre })
}

pub(crate) fn read_operation(root: &Node<'_>, tool: &Tool, peaks_hz: &[f64]) -> Result<Operation, MachineError> {
    let o = root
        .table("operation")?
        .ok_or_else(|| root.missing("operation", "the cut ([operation] with immersion, milling, feed_per_tooth)"))?;
    o.finish(&[
        "immersion",
        "radial_depth",
        "milling",
        "feed_per_tooth",
        "axial_depth",
        "spindle_speed",
        "speed_range",
    ])?;
    let immersion =
        match (o.get("immersion"), o.quantity("radial_depth", &Field { what: "the radial depth", ..DIAMETER })?) {
            (Some(v), None) => {
                v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).filter(|r| *r > 0.0 && *r <= 1.0).ok_or_else(
                    || o.err("immersion", "the radial immersion a_e/D must be a number in (0, 1] (1 = slotting)"),
                )?
            }
            (None, Some(ae)) if ae > 0.0 && ae <= tool.diameter => ae / tool.diameter,
            (None, Some(ae)) => {
                return Err(o.err(
                    "radial_depth",
                    format!(
                        "a_e = {} mm must be in (0, D = {} mm]",
                        units::short(ae * 1e3),
                        units::short(tool.diameter * 1e3)
                    ),
                ));
            }
            (Some(_), Some(_)) => {
                return Err(o.err("radial_depth", "give either immersion (a_e/D) or radial_depth, not both"));
            }
            (None, None) => {
                return Err(o.missing("immersion", "the radial immersion a_e/D (1 = slotting) or radial_depth"));
            }
        };
    let milling = match o.choice("milling", &["up", "down"])?.as_deref() {
        Some("up") => Milling::Up,
        Some(_) => Milling::Down,
        None => return Err(o.missing("milling", "\"up\" or \"down\"")),
    };
    let feed_per_tooth = o
        .quantity("feed_per_tooth", &FEED)?
        .ok_or_else(|| o.missing("feed_per_tooth", "the feed per tooth, e.g. \"0.05 mm\""))?;
    let axial_depth = o.quantity("axial_depth", &DEPTH)?;
    let rpm = |w: f64| w * 60.0 / (2.0 * PI);
    let spindle_speed_rpm = o.quantity("spindle_speed", &SPEED)?.map(rpm);
    let speed_range_rpm = match o.get("speed_range") {
        None => {
            // tooth passing from a tenth of the lowest mode to 1.5 × the highest: the lobes of every mode
            let z = tool.teeth as f64;
            let lo = peaks_hz.iter().copied().fold(f64::INFINITY, f64::min) * 60.0 / z * 0.1;
            let hi = peaks_hz.iter().copied().fold(0.0, f64::max) * 60.0 / z * 1.5;
            (lo.max(100.0), hi.min(3e5))
        }
        Some(toml::Value::Array(a)) if a.len() == 2 => {
            let lo = rpm(o.quantity_value("speed_range", &a[0], &SPEED)?);
            let hi = rpm(o.quantity_value("speed_range", &a[1], &SPEED)?);
            if lo >= hi {
                return Err(o.err("speed_range", "give [lowest, highest] with lowest < highest"));
            }
            (lo, hi)
        }
        Some(_) => return Err(o.err("speed_range", "expected two speeds, e.g. [\"2000 rpm\", \"20000 rpm\"]")),
    };
    Ok(Operation { immersion, milling, feed_per_tooth, axial_depth, spindle_speed_rpm, speed_range_rpm })
}

pub(crate) fn read_actuator(root: &Node<'_>) -> Result<Option<Actuator>, MachineError> {
    let Some(a) = root.table("actuator")? else { return Ok(None) };
    a.finish(&["axis", "frequency", "damping", "force_limit"])?;
    let d = Actuator::default();
    let axis = match a.choice("axis", &["x", "y"])?.as_deref() {
        Some("y") => Axis::Y,
        Some(_) => Axis::X,
        None => return Err(a.missing("axis", "the axis the actuator pushes along, \"x\" or \"y\"")),
    };
    let frequency_hz = a
        .quantity(
            "frequency",
            &Field { what: "the actuator's suspension frequency", range: (2.0 * PI * 0.01, 2.0 * PI * 1e4), ..FREQ },
        )?
        .map_or(d.frequency_hz, |w| w / (2.0 * PI));
    let damping = a.quantity("damping", &Field { range: (1e-4, 2.0), ..DAMPING })?.unwrap_or(d.damping);
    let force_limit = a
        .quantity("force_limit", &FORCE_LIMIT)?
        .ok_or_else(|| a.missing("force_limit", "the actuator's command limit, e.g. \"27 N\""))?;
    Ok(Some(Actuator { axis, frequency_hz, damping, force_limit }))
}

pub(crate) fn read_controller(root: &Node<'_>) -> Result<Option<ControllerChoice>, MachineError> {
    let Some(c) = root.table("controller")? else { return Ok(None) };
    c.finish(&["structure", "parameters", "set"])?;
    let structure = c
        .choice("structure", &["off", "pid", "fopid", "adrc_fopid"])?
        .ok_or_else(|| c.missing("structure", "off, pid, fopid or adrc_fopid"))?;
    let parameters = c.string("parameters")?.map(PathBuf::from);
    let mut set = Vec::new();
    if let Some(s) = c.table("set")? {
        for (k, v) in s_entries(&s) {
            let text = match v {
                toml::Value::String(s) => s.clone(),
                toml::Value::Integer(i) => i.to_string(),
                toml::Value::Float(x) => format!("{x:e}"),
                toml::Value::Boolean(b) => b.to_string(),
                other => return Err(s.err(&k, format!("expected a value, found a {}", other.type_str()))),
            };
            set.push((k, text));
        }
    }
    Ok(Some(ControllerChoice { structure, parameters, set }))
}

/// All entries of a table node (marking them used).
fn s_entries<'a>(n: &Node<'a>) -> Vec<(String, &'a toml::Value)> {
    n.keys().into_iter().filter_map(|k| n.get(&k).map(|v| (k, v))).collect()
}
