// What the server does with a `set`'s labels (scene_json.cpp's apply_labels): all, then only,
// then styles by id, then blend and alone; an id the map does not hold is refused.
import type { LabelsPatch, LabelsState } from '../src/protocol/messages';

export function applyLabelsPatch(labels: LabelsState, patch: LabelsPatch): LabelsState {
  const out = structuredClone(labels);
  const styleOf = (id: string) => {
    const style = out.styles[id];
    if (!style) throw new Error(`invalid_value at /labels/styles/${id}`);
    return style;
  };
  if (patch.all) {
    for (const style of Object.values(out.styles)) Object.assign(style, patch.all);
  }
  if (patch.only) {
    for (const style of Object.values(out.styles)) style.visible = false;
    for (const id of patch.only) styleOf(String(id)).visible = true;
  }
  for (const [id, style] of Object.entries(patch.styles ?? {})) {
    Object.assign(styleOf(id), structuredClone(style));
  }
  if (patch.blend !== undefined) out.blend = patch.blend;
  if (patch.alone !== undefined) out.alone = patch.alone;
  return out;
}
