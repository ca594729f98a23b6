//! The node hierarchy: scene roots, depth-first traversal and local transforms.

use super::Loader;
use anyhow::{anyhow, bail};
use glam::{Mat4, Quat, Vec3};
use gltf::json;

/// Deepest node hierarchy we follow.
const MAX_NODE_DEPTH: usize = 1024;

impl Loader<'_> {
    /// The root nodes to traverse: the default scene (or scenes[0]); with no scenes, every
    /// root node.
    pub(super) fn scene_roots(&mut self) -> anyhow::Result<Vec<usize>> {
        let root = self.root;
        let default_scene = root.scene.map(|s| s.value()).or(if root.scenes.is_empty() {
            None
        } else {
            Some(0)
        });
        if let Some(si) = default_scene {
            let scene = root
                .scenes
                .get(si)
                .ok_or_else(|| anyhow!("default scene {si} does not exist"))?;
            return Ok(scene.nodes.iter().map(|n| n.value()).collect());
        }
        self.warnings
            .push("the file has no scenes: rendering every root node".into());
        let mut is_child = vec![false; root.nodes.len()];
        for n in &root.nodes {
            for c in n.children.iter().flatten() {
                if let Some(f) = is_child.get_mut(c.value()) {
                    *f = true;
                }
            }
        }
        Ok((0..root.nodes.len()).filter(|&i| !is_child[i]).collect())
    }

    /// Depth-first pre-order traversal (the first camera found wins).
    pub(super) fn traverse(&mut self, roots: &[usize]) -> anyhow::Result<()> {
        let root = self.root;
        let mut visited = vec![false; root.nodes.len()];
        let mut stack: Vec<(usize, Mat4, usize)> = roots
            .iter()
            .rev()
            .map(|&n| (n, Mat4::IDENTITY, 0))
            .collect();
        while let Some((ni, parent, depth)) = stack.pop() {
            let Some(node) = root.nodes.get(ni) else {
                self.warnings.push(format!(
                    "node {ni} does not exist (index out of range): skipped"
                ));
                continue;
            };
            if visited[ni] {
                self.warnings.push(format!(
                    "node {ni} is reached twice (cycle or shared child): visited once only"
                ));
                continue;
            }
            visited[ni] = true;
            if depth > MAX_NODE_DEPTH {
                bail!("node hierarchy deeper than {MAX_NODE_DEPTH} levels");
            }
            let Some(world) = self.node_world(ni, node, parent) else {
                continue;
            };
            self.node_contents(ni, node, world)?;
            for c in node.children.iter().flatten().rev() {
                stack.push((c.value(), world, depth + 1));
            }
        }
        Ok(())
    }

    /// Node `ni`'s world transform under `parent`; None with a warning (node and children
    /// skipped) if its local matrix is unusable or the product is not finite.
    fn node_world(&mut self, ni: usize, node: &json::Node, parent: Mat4) -> Option<Mat4> {
        let local = match node_local_matrix(node) {
            Ok(m) => m,
            Err(e) => {
                self.warnings
                    .push(format!("node {ni}: {e}; node and children skipped"));
                return None;
            }
        };
        let world = parent * local;
        if !world.is_finite() {
            self.warnings
                .push(format!("node {ni}: world transform is not finite; skipped"));
            return None;
        }
        Some(world)
    }

    /// Add what node `ni` carries, placed at `world`: its camera, its mesh, its punctual light.
    fn node_contents(&mut self, ni: usize, node: &json::Node, world: Mat4) -> anyhow::Result<()> {
        if let Some(ci) = node.camera {
            self.camera_node(ni, ci.value(), world)?;
        }
        if let Some(mi) = node.mesh {
            self.mesh_node(ni, mi.value(), world)?;
        }
        if let Some(l) = node
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
        {
            self.light_node(ni, l.light.value(), world)?;
        }
        Ok(())
    }
}

/// A node's local matrix: `matrix` if present, else T · R · S.
fn node_local_matrix(node: &json::Node) -> Result<Mat4, String> {
    let m = if let Some(m) = node.matrix {
        // glTF: a node matrix is an affine TRS; a projective bottom row cannot be one.
        if m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0 {
            return Err(format!(
                "matrix is not affine (its last row is [{}, {}, {}, {}], must be [0, 0, 0, 1])",
                m[3], m[7], m[11], m[15]
            ));
        }
        Mat4::from_cols_array(&m)
    } else {
        let t = Vec3::from(node.translation.unwrap_or([0.0; 3]));
        let s = Vec3::from(node.scale.unwrap_or([1.0; 3]));
        let r = node.rotation.map(|q| q.0).unwrap_or([0.0, 0.0, 0.0, 1.0]);
        let q = Quat::from_array(r);
        let len = q.length();
        if !(len.is_finite() && len > 1e-6) {
            return Err("rotation quaternion has zero or non-finite length".into());
        }
        Mat4::from_scale_rotation_translation(s, q / len, t)
    };
    if m.is_finite() {
        Ok(m)
    } else {
        Err("transform is not finite".into())
    }
}
