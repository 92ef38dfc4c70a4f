//! Consistency checks run by every writer before it opens a file.
//!
//! `Fabric::curves` indexes nodes and specs directly, so a fabric loaded from
//! hand-edited JSON with a dangling index would panic inside an exporter.
//! Checking here turns that into an [`ExportError`] error instead.

use super::error::ExportError;
use crate::topology::Fabric;

/// Indices in range and positions finite.
pub(crate) fn check_structure(fabric: &Fabric) -> Result<(), ExportError> {
    let node_count = fabric.nodes.len();
    let spec_count = fabric.meta.yarns.len();
    for (yi, yarn) in fabric.yarns.iter().enumerate() {
        if yarn.spec >= spec_count {
            return Err(ExportError::SpecOutOfRange {
                yarn: yi,
                spec: yarn.spec,
                count: spec_count,
            });
        }
        for (pi, p) in yarn.points.iter().enumerate() {
            if p.node >= node_count {
                return Err(ExportError::NodeOutOfRange {
                    yarn: yi,
                    point: pi,
                    node: p.node,
                    count: node_count,
                });
            }
        }
    }
    let point_exists =
        |r: &crate::topology::PointRef| fabric.yarns.get(r.yarn).is_some_and(|y| r.point < y.points.len());
    for (ci, c) in fabric.contacts.iter().enumerate() {
        let partner_ok = c.partner.is_none_or(|n| n < node_count);
        if c.node >= node_count || !point_exists(&c.front) || !point_exists(&c.back) || !partner_ok {
            return Err(ExportError::ContactOutOfRange { contact: ci });
        }
    }
    if let Some(node) = fabric.nodes.iter().position(|n| n.x.iter().any(|c| !c.is_finite())) {
        return Err(ExportError::NonFinitePosition { node });
    }
    Ok(())
}

/// [`check_structure`] plus radii that a tube or capsule can be drawn with.
pub(crate) fn check_drawable(fabric: &Fabric) -> Result<(), ExportError> {
    check_structure(fabric)?;
    for (spec, y) in fabric.meta.yarns.iter().enumerate() {
        if !(y.radius.is_finite() && y.radius > 0.0) {
            return Err(ExportError::BadRadius { spec, radius: y.radius });
        }
    }
    Ok(())
}
