// The part list of the page (docs/viewer.md "Parts"): a row per part — a check box that shows or
// hides it, its colour, its name (its id where the file names none) and "isolate" — a search box
// that filters the rows by name or id, and "show all". Names come from the file: they go in as
// text, never as markup. The scripting API's parts() and setPartsVisible() (window.dynpm) act
// on the same PartView, so a test drives the list and the API alike.
import { element } from './fringe.js';

export class PartList {
  // view: a PartView; changed(): redraws the model after a change of visibility.
  constructor(view, changed) {
    this.view = view;
    this.changed = changed;
    this.root = document.getElementById('parts');
    this.list = document.getElementById('part-list');
    this.search = document.getElementById('part-search');
    this.count = document.getElementById('part-count');
    this.rows = new Map();  // id → {row, box, label text}
    this.search.addEventListener('input', () => this.filter());
    document.getElementById('parts-show-all').addEventListener('click', () => this.set(this.view.ids(), true));
    this.root.hidden = false;
    this.refresh();
  }

  // Shows (hides) parts `ids`, redraws and updates the rows.
  set(ids, visible) {
    if (this.view.setVisible(ids, visible)) this.changed();
    this.refresh();
  }

  isolate(id) {
    const others = this.view.ids().filter((k) => k !== id);
    const a = this.view.setVisible(others, false), b = this.view.setVisible([id], true);
    if (a || b) this.changed();
    this.refresh();
  }

  // Rows for parts that arrived since, and every check box as the view has it.
  refresh() {
    const parts = this.view.list();
    for (const { id, name } of parts) if (!this.rows.has(id)) this.addRow(id, name);
    for (const { id, visible } of parts) this.rows.get(id).box.checked = visible;
    const hidden = parts.filter((p) => !p.visible).length;
    this.count.textContent = `${parts.length} part${parts.length === 1 ? '' : 's'}${hidden ? `, ${hidden} hidden` : ''}`;
    this.filter();
  }

  addRow(id, name) {
    const box = element('input');
    Object.assign(box, { type: 'checkbox', checked: true, title: 'show / hide' });
    box.addEventListener('change', () => this.set([id], box.checked));
    const label = name ?? `part ${id}`;
    const text = element('span', { className: 'part-name' }, label);
    text.title = name ? `${name} (id ${id})` : `part id ${id}`;
    const isolate = element('button', {}, 'isolate');
    isolate.type = 'button';
    isolate.addEventListener('click', () => this.isolate(id));
    const row = element('li', {}, box, element('span', { className: 'swatch', background: this.view.colourStyle(id) }),
      text, element('span', { className: 'muted' }, name ? String(id) : ''), isolate);
    row.dataset.part = String(id);
    // Rows in id order: before the first row of a larger id.
    const next = [...this.rows.keys()].filter((k) => k > id).sort((a, b) => a - b)[0];
    this.list.insertBefore(row, next === undefined ? null : this.rows.get(next).row);
    this.rows.set(id, { row, box, key: `${label} ${id}`.toLowerCase() });
  }

  // Rows whose name or id holds the search text.
  filter() {
    const q = this.search.value.trim().toLowerCase();
    for (const { row, key } of this.rows.values()) row.hidden = q !== '' && !key.includes(q);
  }
}

// window.dynpm.parts() → [{id, name, visible}] (name null where the file has none) and
// setPartsVisible(ids, visible); `list()` gives the PartList once the base mesh is in.
export function addPartsApi(list) {
  Object.assign((window.dynpm ??= {}), {
    parts: () => list()?.view.list() ?? [],
    setPartsVisible(ids, visible) {
      const l = list();
      if (!l) throw new Error('setPartsVisible: the model is not loaded yet');
      const known = new Set(l.view.ids());
      const wanted = [ids].flat().map(Number);
      const unknown = wanted.filter((id) => !known.has(id));
      if (unknown.length) throw new RangeError(`setPartsVisible: no part ${unknown.join(', ')}`);
      l.set(wanted, Boolean(visible));
    },
  });
}
