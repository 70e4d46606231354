//! Ports: the value references of each component that the run reads or
//! writes, resolved once during assembly and batched into one FMI call per
//! type and direction (outputs after each step, inputs before it, recorded
//! variables at output points), with buffers allocated once. [`Route`]s copy
//! connected outputs into inputs (with an optional linear transformation);
//! [`Components`] owns the running instances and closes them all, before any
//! library is unloaded, however the run ends.

use crate::error::FmuError;
use crate::import::{Fmu, Instance};
use model_description::{ScalarType, ScalarVariable};
use ssp::Linear;

/// The FMI value type a variable is read and written with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Api {
    Real,
    Integer,
    Boolean,
}

/// The API type of a variable (enumerations are Integer); None for String.
pub(crate) fn api_of(v: &ScalarVariable) -> Option<Api> {
    match v.scalar_type().api_type() {
        ScalarType::Real => Some(Api::Real),
        ScalarType::Integer => Some(Api::Integer),
        ScalarType::Boolean => Some(Api::Boolean),
        _ => None,
    }
}

/// Variables of one component read or written together in one FMI call per type.
#[derive(Default)]
pub(crate) struct Ports {
    real_vrs: Vec<u32>,
    real: Vec<f64>,
    int_vrs: Vec<u32>,
    int: Vec<i32>,
    bool_vrs: Vec<u32>,
    boolean: Vec<bool>,
}

impl Ports {
    /// Slot of (api, vr), added if new.
    pub(crate) fn slot(&mut self, api: Api, vr: u32) -> usize {
        let (vrs, len) = match api {
            Api::Real => (&mut self.real_vrs, self.real.len()),
            Api::Integer => (&mut self.int_vrs, self.int.len()),
            Api::Boolean => (&mut self.bool_vrs, self.boolean.len()),
        };
        if let Some(i) = vrs.iter().position(|&v| v == vr) {
            return i;
        }
        vrs.push(vr);
        match api {
            Api::Real => self.real.push(0.0),
            Api::Integer => self.int.push(0),
            Api::Boolean => self.boolean.push(false),
        }
        len
    }

    /// Get every variable from the instance.
    #[inline]
    pub(crate) fn read(&mut self, inst: &mut Instance) -> Result<(), FmuError> {
        if !self.real_vrs.is_empty() {
            inst.get_real(&self.real_vrs, &mut self.real)?;
        }
        self.read_other(inst)
    }

    /// Get the Integer and Boolean variables from the instance.
    #[inline]
    fn read_other(&mut self, inst: &mut Instance) -> Result<(), FmuError> {
        if !self.int_vrs.is_empty() {
            inst.get_integer(&self.int_vrs, &mut self.int)?;
        }
        if !self.bool_vrs.is_empty() {
            inst.get_boolean(&self.bool_vrs, &mut self.boolean)?;
        }
        Ok(())
    }

    /// Set every variable of the instance.
    #[inline]
    pub(crate) fn write(&self, inst: &mut Instance) -> Result<(), FmuError> {
        if !self.real_vrs.is_empty() {
            inst.set_real(&self.real_vrs, &self.real)?;
        }
        self.write_other(inst)
    }

    /// Set the Integer and Boolean variables of the instance.
    #[inline]
    fn write_other(&self, inst: &mut Instance) -> Result<(), FmuError> {
        if !self.int_vrs.is_empty() {
            inst.set_integer(&self.int_vrs, &self.int)?;
        }
        if !self.bool_vrs.is_empty() {
            inst.set_boolean(&self.bool_vrs, &self.boolean)?;
        }
        Ok(())
    }

    /// The Real values (in slot order).
    pub(crate) fn reals(&self) -> &[f64] {
        &self.real
    }

    /// The value in a slot, as f64.
    pub(crate) fn get(&self, api: Api, i: usize) -> f64 {
        match api {
            Api::Real => self.real[i],
            Api::Integer => f64::from(self.int[i]),
            Api::Boolean => f64::from(u8::from(self.boolean[i])),
        }
    }
}

/// One connection, resolved: from an output slot of `src` to an input slot of `dst`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Route {
    pub src: usize,
    pub src_slot: usize,
    pub dst: usize,
    pub dst_slot: usize,
    pub api: Api,
    pub linear: Option<Linear>,
}

/// A recorded variable: component, type, slot in the component's recorded ports.
pub(crate) type Probe = (usize, Api, usize);

/// One running component.
pub(crate) struct Component {
    pub name: String,
    // Field order is drop order: the instance goes before the FMU handle
    // (the library itself stays loaded until both are gone).
    pub inst: Instance,
    pub fmu: Fmu,
    pub outputs: Ports,
    pub inputs: Ports,
    pub recorded: Ports,
    /// Routes ending here (copies: the stepping loop reads them without the route list).
    pub incoming: Vec<Route>,
}

/// The components, closing every instance before any library is unloaded
/// (see `Instance::close`): on success and on every failure path.
pub(crate) struct Components(pub Vec<Component>);

impl std::ops::Deref for Components {
    type Target = Vec<Component>;
    fn deref(&self) -> &Vec<Component> {
        &self.0
    }
}

impl std::ops::DerefMut for Components {
    fn deref_mut(&mut self) -> &mut Vec<Component> {
        &mut self.0
    }
}

impl Drop for Components {
    fn drop(&mut self) {
        for c in self.0.iter_mut() {
            c.inst.close();
        }
    }
}

impl Components {
    /// Copy the connected outputs into component `i`'s inputs and set them.
    #[inline]
    pub(crate) fn set_inputs(&mut self, i: usize) -> Result<(), FmuError> {
        if self.0[i].incoming.is_empty() {
            return Ok(());
        }
        self.copy_inputs(i);
        let c = &mut self.0[i];
        c.inputs.write(&mut c.inst)
    }

    /// Copy the connected outputs into component `i`'s input ports.
    #[inline]
    fn copy_inputs(&mut self, i: usize) {
        for k in 0..self.0[i].incoming.len() {
            let r = self.0[i].incoming[k];
            let src = &self.0[r.src].outputs;
            match r.api {
                Api::Real => {
                    let mut x = src.real[r.src_slot];
                    if let Some(l) = r.linear {
                        x = l.factor * x + l.offset;
                    }
                    self.0[i].inputs.real[r.dst_slot] = x;
                }
                Api::Integer => {
                    let x = src.int[r.src_slot];
                    self.0[i].inputs.int[r.dst_slot] = x;
                }
                Api::Boolean => {
                    let x = src.boolean[r.src_slot];
                    self.0[i].inputs.boolean[r.dst_slot] = x;
                }
            }
        }
    }

    /// One Gauss–Seidel step of component `i`: its inputs from the connected outputs,
    /// `fmi2DoStep(t, h)`, its outputs read (the Real set, step and get as one
    /// [`Instance::step_reals`]).
    #[inline]
    pub(crate) fn advance(&mut self, i: usize, t: f64, h: f64) -> Result<(), FmuError> {
        self.copy_inputs(i);
        let c = &mut self.0[i];
        c.inputs.write_other(&mut c.inst)?;
        let ins = (c.inputs.real_vrs.as_slice(), c.inputs.real.as_slice());
        c.inst.step_reals(ins, t, h, (&c.outputs.real_vrs, &mut c.outputs.real))?;
        c.outputs.read_other(&mut c.inst)
    }

    /// Read component `i`'s connected outputs.
    #[inline]
    pub(crate) fn read_outputs(&mut self, i: usize) -> Result<(), FmuError> {
        let c = &mut self.0[i];
        c.outputs.read(&mut c.inst)
    }

    /// `fmi2DoStep(t, h)` of component `i`, then read its outputs.
    #[inline]
    pub(crate) fn step(&mut self, i: usize, t: f64, h: f64) -> Result<(), FmuError> {
        let c = &mut self.0[i];
        c.inst.do_step(t, h)?;
        c.outputs.read(&mut c.inst)
    }

    /// Read every recorded variable into `row` (in `probes` order).
    pub(crate) fn sample(&mut self, probes: &[Probe], row: &mut Vec<f64>) -> Result<(), FmuError> {
        for c in self.0.iter_mut() {
            c.recorded.read(&mut c.inst)?;
        }
        row.clear();
        row.extend(probes.iter().map(|&(c, api, slot)| self.0[c].recorded.get(api, slot)));
        Ok(())
    }
}
