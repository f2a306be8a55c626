//! Errors of the model stage blamed on the scene key that caused them, where one can tell:
//! the model works on resolved data and reports what failed (a singular rotor stiffness, a
//! stator that is a mechanism, a placement that never meets the rotor); these functions find
//! the dotted key behind it and name it with the file and line (`Model::from_scene`) or, at a
//! speed, the dotted key (`Model::case`).

use crate::error::{Error, ModelError};
use crate::resolve::{Resolved, RotorInput};
use crate::scene::LoadedScene;

/// A placement along `approach_deg` that never meets the rotor (an error of the case at a
/// speed, where the clearance is known) names the key `stator.<i>.approach_deg` of stator `i`.
pub(super) fn approach(i: usize, e: ModelError) -> ModelError {
    match e {
        ModelError::Inconsistent { what, message } if message.ends_with("check approach_deg") => {
            ModelError::Inconsistent {
                what,
                message: format!("{message} (`stator.{i}.approach_deg`)"),
            }
        }
        e => e,
    }
}

/// An FE rotor whose bearings do not hold it (its stiffness matrix singular: it pivots) blamed
/// on the key that made it so, with the file and line, where one can tell: the first bearing
/// with a zero direct stiffness (`k_xx` or `k_yy` zero at every tabulated speed) —
/// `rotor.bearing.<i>.stiffness` — else the first bearing on the node of an earlier one —
/// `rotor.bearing.<i>.node`. Any other error, or a singular rotor neither explains, is returned
/// as it is (it names `rotor.bearing`).
pub(super) fn bearings(ls: &LoadedScene, r: &Resolved, e: Error) -> Error {
    let pivots = matches!(&e, Error::Model(ModelError::Singular { what, detail })
        if what == "rotor stiffness" && detail.contains("do not hold the rotor"));
    let RotorInput::Fe(f) = &r.rotor else {
        return e;
    };
    if !pivots {
        return e;
    }
    let bearings = &f.data.bearings;
    let pivot = "the rotor pivots about its other bearings (its stiffness matrix is singular)";
    if let Some((i, b)) = bearings
        .iter()
        .enumerate()
        .find(|(_, b)| b.k.iter().all(|k| k[0] == 0.0 || k[3] == 0.0))
    {
        // The key the scene gives the coefficients by: `stiffness`, else `kxx`/`kyy`.
        let by_stiffness = match &ls.scene.rotor {
            crate::scene::RotorSpec::Fe(s) => {
                s.bearing.get(i).is_none_or(|b| b.stiffness.is_some())
            }
            crate::scene::RotorSpec::Jeffcott(_) => true,
        };
        let name = if by_stiffness {
            "stiffness"
        } else if b.k.iter().all(|k| k[0] == 0.0) {
            "kxx"
        } else {
            "kyy"
        };
        return ls
            .invalid(
                &format!("rotor.bearing.{i}.{name}"),
                format!(
                    "the bearing on node {} has a zero direct stiffness (k_xx or k_yy): {pivot}",
                    b.node
                ),
            )
            .into();
    }
    for (j, b) in bearings.iter().enumerate() {
        if let Some(i) = bearings[..j].iter().position(|a| a.node == b.node) {
            return ls
                .invalid(
                    &format!("rotor.bearing.{j}.node"),
                    format!(
                        "node {} already holds bearing {i}: two bearings on one node act as one, and {pivot}",
                        b.node
                    ),
                )
                .into();
        }
    }
    e
}

/// A stator error of the model stage blamed on the key that made it, with the file and line,
/// where one can tell: a meshed stator that is a mechanism — `stator.<i>.springs.<j>.stiffness`
/// for a grounded spring of zero stiffness, `stator.<i>.fixed` when it has no support at all
/// (no `fixed`, `fixed_x`, `fixed_y`, `fixed_z`, no spring) or its supports hold no node of its
/// elements, `stator.<i>.frames` when they lie on curve groups without a `frames` entry; a placement along `approach_deg`
/// that never meets the rotor — `stator.<i>.approach_deg`. Otherwise `e` as it is.
pub(super) fn stators(ls: &LoadedScene, e: Error) -> Error {
    use crate::scene::StatorSpec;
    let stators = &ls.scene.stators;
    let index = |what: &str| {
        stators
            .iter()
            .position(|s| what.starts_with(&format!("stator `{}`", s.name())))
    };
    let key = match &e {
        Error::Model(ModelError::Factorisation { what, .. }) => {
            let Some(i) = index(what) else { return e };
            let StatorSpec::Mesh(m) = &stators[i] else {
                return e;
            };
            match m.springs.iter().position(|sp| sp.stiffness.contains(&0.0)) {
                Some(j) => format!("stator.{i}.springs.{j}.stiffness"),
                None if m.fixed.is_empty() => format!("stator.{i}.fixed"),
                None => return e,
            }
        }
        Error::Model(ModelError::Inconsistent { what, message })
            if message.contains("hold no node of the stator's cells or frames") =>
        {
            let Some(i) = index(what) else { return e };
            if message.contains("carry no `frames` entry") {
                format!("stator.{i}.frames")
            } else {
                format!("stator.{i}.fixed")
            }
        }
        Error::Model(ModelError::Inconsistent { what, message })
            if message.starts_with("`contact_damping`") =>
        {
            let Some(i) = index(what) else { return e };
            format!("stator.{i}.contact_damping")
        }
        Error::Model(ModelError::Inconsistent { what, message })
            if message.contains("approach_deg") =>
        {
            let Some(i) = index(what) else { return e };
            format!("stator.{i}.approach_deg")
        }
        _ => return e,
    };
    ls.invalid(&key, e.to_string()).into()
}
