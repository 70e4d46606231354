//! The InertialActuator adapter: the shared adapter checks.

use fmi2_export::table::checks::{ready, stepped};
use fmu_inertial_actuator::InertialActuator;
use machine_structure::ActuatorParams;

type M = InertialActuator;

fmi2_export::adapter_tests! {
    model: M,
    valid: [],
    params: [{
        let mut p = ActuatorParams { direction_angle: 0.5, ..Default::default() };
        p.a[1][0] = 0.7;
        p
    }],
    work: Work::Bound("internal_step"),
    step: 1e-5,
    states: { stepped: stepped::<M>(10.0, 200, 1e-5), fresh: ready::<M>, seed: 0x2545_f491_4f6c_dd1d, tries: 1000 },
}
