//! The systems of [`super::DesignPlugin`]: each reads, calls one core function, writes.

use super::*;
use crate::model::edit::apply;

/// Applies the requests of this update to the design, in order.
pub fn apply_edits(
    mut edits: MessageReader<EditDesign>,
    mut settings_edits: MessageReader<EditSettings>,
    mut design: ResMut<Design>,
    mut settings: ResMut<Settings>,
    mut state: ResMut<PipelineState>,
    mut status: ResMut<SceneStatus>,
) {
    for EditDesign(edit) in edits.read() {
        let scene = design.0.get_or_insert_with(|| Scene::new("design", Vec::new()));
        match apply(scene, edit) {
            Ok(()) => state.dirty = true,
            Err(e) => status.error = Some(e.to_string()),
        }
    }
    for EditSettings(edit) in settings_edits.read() {
        match edit {
            SettingsEdit::SetFrictionModel(m) => settings.0.statics.friction_model = *m,
        }
        state.dirty = true;
    }
}

/// Runs the pipeline when the design or the settings changed.
pub fn run_pipeline(
    design: Res<Design>,
    settings: Res<Settings>,
    mut state: ResMut<PipelineState>,
    mut status: ResMut<SceneStatus>,
    mut counters: ResMut<Counters>,
) {
    let (Some(scene), true) = (&design.0, state.dirty) else { return };
    state.dirty = false;
    state.generation += 1;
    match state.pipeline.run(scene, &settings.0) {
        Ok(a) => {
            let s = &a.statics;
            *status = SceneStatus {
                verdict: Some(s.verdict),
                stands: s.stands,
                tension_ratio: s.tension_ratio,
                friction_excess_ratio: s.friction_excess_ratio,
                max_friction_utilization: s.max_friction_utilization,
                timings: a.timings,
                work: a.work,
                error: None,
            };
            counters.runs += 1;
            counters.pieces_recut += a.work.pieces_cut;
            counters.interfaces_redetected += a.work.pairs_detected;
            counters.components_resolved += a.work.components_solved;
            counters.components_reused += a.work.components_reused;
            state.analysis = Some(a);
        }
        Err(e) => {
            *status = SceneStatus { error: Some(e.to_string()), ..Default::default() };
            state.analysis = None;
        }
    }
}

/// Writes block and interface entities after a run: blocks by name (spawned, updated when
/// their mesh or support changed, despawned when gone); interfaces replaced.
pub fn write_entities(
    mut commands: Commands,
    state: Res<PipelineState>,
    mut index: ResMut<BlockIndex>,
    mut written: Local<u64>,
    blocks: Query<(&BlockMesh, &MassCentre, Has<Support>)>,
    interfaces: Query<Entity, With<InterfaceOf>>,
) {
    if *written == state.generation {
        return;
    }
    *written = state.generation;
    interfaces.iter().for_each(|e| commands.entity(e).despawn());
    let Some(a) = &state.analysis else {
        index.0.drain().for_each(|(_, e)| commands.entity(e).despawn());
        return;
    };
    let mut next = HashMap::with_capacity(a.assembly.blocks.len());
    for b in &a.assembly.blocks {
        let mass = MassCentre { mass: b.mass(), centroid: b.mass.centroid, density: b.density };
        let parts = (BlockMesh(b.mesh.clone()), mass);
        let entity = match index.0.remove(&b.name) {
            Some(e) => {
                let same = blocks.get(e).is_ok_and(|(m, c, s)| m.0 == b.mesh && *c == mass && s == b.support);
                if !same {
                    commands.entity(e).insert(parts);
                }
                e
            }
            None => commands.spawn((BlockName(b.name.clone()), parts)).id(),
        };
        if b.support {
            commands.entity(entity).insert(Support);
        } else {
            commands.entity(entity).remove::<Support>();
        }
        next.insert(b.name.clone(), entity);
    }
    index.0.drain().for_each(|(_, e)| commands.entity(e).despawn());
    let entity_of = |body: crate::interfaces::Body| body.block().map(|id| next[&a.assembly.block(id).name]);
    // Interfaces between fixed bodies are never solved: they get no forces.
    let mut results = a.statics.interfaces.iter().peekable();
    for (k, i) in a.interfaces.iter().enumerate() {
        let mut e = commands.spawn((InterfaceOf { a: entity_of(i.a), b: entity_of(i.b) }, InterfaceIndex(k)));
        if let Some(r) = results.next_if(|r| r.index == k) {
            e.insert(InterfaceForces(r.clone()));
        }
    }
    index.0 = next;
}
