// dynpm serve's catalogue page (catalogue.html): the folder's .dpm files from /index.json (the
// entries `dynpm catalogue` writes, docs/batch.md), each with its thumbnail and metadata; a
// filter by name or source, field and part; one opens in the viewer (/view?model=…), two
// selected open side by side (/view?model=…&compare=…). A family file (docs/family.md) lists its
// members, each opened and selected as a variant of its own (&variant=, &compareVariant=). The
// page asks for /index.json again every few seconds (?poll=MS), so files that a running batch
// finishes appear by themselves.
//
// Every string here comes from a file (names, notes, field and part names): it goes into the
// page as text (textContent, attributes), never as markup.

const $ = (id) => document.getElementById(id);
const ui = {
  filter: $('filter'),
  field: $('field-filter'),
  part: $('part-filter'),
  count: $('count'),
  selection: $('selection'),
  compare: $('compare'),
  overlay: $('compare-overlay'),
  clear: $('clear-selection'),
  entries: $('entries'),
  problems: $('problems'),
  empty: $('empty'),
  error: $('error'),
};
const params = new URLSearchParams(location.search);
const pollMs = Math.max(250, Number(params.get('poll') ?? 2000) || 2000);

const state = {
  index: null,  // the last /index.json
  text: '',  // its entries and problems as text: a new index that equals it changes nothing
  selected: [],  // at most two {path, variant} (variant: a family's member, else null), oldest first
  cards: new Map(),  // path → its <article>
  polls: 0,
};

// A path below the served folder as a URL path: each segment encoded, the slashes kept.
export function encodePath(path) {
  return path.split('/').map(encodeURIComponent).join('/');
}
export const fileUrl = (path) => `/files/${encodePath(path)}`;
export const thumbUrl = (path) => `/thumb/${encodePath(path.replace(/\.dpm$/, ''))}.png`;
// The viewer on one model, or two (the second compared with the first); a family file's member
// by its name: &variant= for the first, &compareVariant= for the second (docs/batch.md); the
// second drawn over the first with &compareLayout= (compare_overlay.js).
export function viewerUrl(path, { compare, variant, compareVariant, layout } = {}) {
  const q = new URLSearchParams({ model: fileUrl(path) });
  if (variant != null) q.set('variant', variant);
  if (compare) q.set('compare', fileUrl(compare));
  if (compare && compareVariant != null) q.set('compareVariant', compareVariant);
  if (compare && layout) q.set('compareLayout', layout);
  return `/view?${q}`;
}

// What can be selected to compare: a file, or one member of a family file. The key is the
// selection's identity (a member's name may hold any character, so it is not joined into text).
const choiceKey = (path, variant = null) => JSON.stringify([path, variant]);
const choiceName = ({ path, variant }) => path.replace(/\.dpm$/, '') + (variant == null ? '' : ` [${variant}]`);

function element(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (k === 'text') e.textContent = v;
    else if (k === 'class') e.className = v;
    else e.setAttribute(k, v);
  }
  e.append(...children.filter((c) => c != null));
  return e;
}

const int = (n) => Number(n).toLocaleString('en');
const time = (t) => String(Number(Number(t).toPrecision(4)));
function bytesText(n) {
  if (n >= 1 << 30) return `${(n / (1 << 30)).toFixed(1)} GiB`;
  if (n >= 1 << 20) return `${(n / (1 << 20)).toFixed(1)} MiB`;
  return `${Math.max(1, Math.round(n / 1024))} KiB`;
}
const partName = (p) => (p.name ? `${p.name} (${p.id})` : `part ${p.id}`);
// A family file's members' names (a VARI chunk; docs/FORMAT.md, the entry's "variants").
const variantsOf = (entry) => (Array.isArray(entry.variants) ? entry.variants.map((v) => String(v?.name ?? '')) : []);

// The check box that selects a file (variant null) or a family's member to compare.
function selectBox(path, variant, label) {
  const box = element('input', { type: 'checkbox', class: 'select', 'aria-label': `select ${label} to compare`, 'data-key': choiceKey(path, variant) });
  box.checked = state.selected.some((c) => c.path === path && c.variant === variant);
  box.addEventListener('change', () => toggle({ path, variant }, box.checked));
  return box;
}

// A family's members, each a link to the viewer on it and a check box to compare it.
function memberList(entry) {
  const member = ({ name, steps, first_time: t0, last_time: t1 }) =>
    element('li', { 'data-variant': name },
      selectBox(entry.path, name, `${entry.name} ${name}`), ' ',
      element('a', { href: viewerUrl(entry.path, { variant: name }), text: name }),
      element('span', { class: 'muted', text: ` ${int(steps)} steps${steps > 1 ? ` (t ${time(t0)} … ${time(t1)})` : ''}` }));
  return element('ul', { class: 'variants' }, ...entry.variants.map(member));
}

function card(entry) {
  const path = entry.path;
  const picture = entry.thumbnail
    ? element('img', { class: 'thumb', src: thumbUrl(path), alt: `${entry.name}, last step`, loading: 'lazy' })
    : element('div', { class: 'thumb placeholder', text: 'no thumbnail' });
  const open = element('a', { href: viewerUrl(path), class: 'open', text: entry.name });
  // A family's stored steps are in no time order (docs/family.md): its members' time range.
  const members = Array.isArray(entry.variants) ? entry.variants : [];
  const [t0, t1] = members.length ? [Math.min(...members.map((v) => v.first_time)), Math.max(...members.map((v) => v.last_time))] : [entry.first_time, entry.last_time];
  const times = entry.steps > 1 ? ` (t ${time(t0)} … ${time(t1)})` : '';
  const fields = entry.fields.length ? entry.fields.map((f) => `${f.name}${f.unit ? ` [${f.unit}]` : ''} (${f.location})`).join(', ') : 'none';
  const parts = entry.parts.length <= 6 ? entry.parts.map(partName).join(', ') : `${entry.parts.length} parts`;
  const variants = variantsOf(entry);
  const article = element(
    'article',
    { class: 'entry', 'data-path': path },
    element('a', { href: viewerUrl(path), tabindex: '-1' }, picture),
    element('h2', {}, open),
    element('p', { class: 'facts muted', text: path + (entry.source ? ` · from ${entry.source}` : '') }),
    element('p', { class: 'facts', text: `${int(entry.vertices)} nodes · ${int(entry.faces)} faces · ${int(entry.steps)} ${variants.length ? 'stored ' : ''}steps${times}` }),
    element('p', { class: 'facts', text: `fields: ${fields}` }),
    element('p', { class: 'facts', text: `parts: ${parts}` }),
    element('p', { class: 'facts muted', text: `${bytesText(entry.bytes)} · built ${entry.built.replace('T', ' ').replace('Z', ' UTC')}` }),
    variants.length
      ? element('p', { class: 'facts', text: `a family of ${variants.length} variants (one hierarchy: compared per vertex); tick two to compare:` })
      : null,
    variants.length ? memberList(entry) : element('label', { class: 'row muted' }, selectBox(path, null, entry.name), 'select to compare'),
  );
  return article;
}

function matches(entry) {
  const text = ui.filter.value.trim().toLowerCase();
  if (text && ![entry.name, entry.path, entry.source, ...variantsOf(entry)].some((s) => String(s).toLowerCase().includes(text))) return false;
  if (ui.field.value && !entry.fields.some((f) => f.name === ui.field.value)) return false;
  if (ui.part.value && !entry.parts.some((p) => partName(p) === ui.part.value)) return false;
  return true;
}

// A <select>'s options made again from the names in the index, keeping the chosen one.
function fillChoices(select, label, names) {
  const chosen = select.value;
  select.replaceChildren(element('option', { value: '', text: label }), ...[...names].sort().map((n) => element('option', { value: n, text: n })));
  select.value = names.has(chosen) ? chosen : '';
}

function render() {
  const { entries, problems } = state.index;
  fillChoices(ui.field, 'any field', new Set(entries.flatMap((e) => e.fields.map((f) => f.name))));
  fillChoices(ui.part, 'any part', new Set(entries.flatMap((e) => e.parts.map(partName))));
  state.cards = new Map(entries.map((e) => [e.path, card(e)]));
  const present = new Set(entries.flatMap((e) => [choiceKey(e.path), ...variantsOf(e).map((v) => choiceKey(e.path, v))]));
  state.selected = state.selected.filter((c) => present.has(choiceKey(c.path, c.variant)));
  ui.entries.replaceChildren(...state.cards.values());
  ui.problems.replaceChildren(...problems.map((p) => element('li', { text: `cannot read ${p}` })));
  ui.problems.hidden = problems.length === 0;
  applyFilter();
  updateSelection();
}

function applyFilter() {
  const entries = state.index?.entries ?? [];
  let shown = 0, variants = 0, shownVariants = 0;
  for (const e of entries) {
    const visible = matches(e);
    state.cards.get(e.path).hidden = !visible;
    const k = Math.max(1, variantsOf(e).length);  // a family's members, or the file itself
    shown += visible;
    variants += k;
    shownVariants += visible ? k : 0;
  }
  const files = shown === entries.length ? `${entries.length} files` : `${shown} of ${entries.length} files`;
  // With family files, the variants too: a family file holds several.
  ui.count.textContent = variants === entries.length ? files : `${files} · ${shownVariants === variants ? variants : `${shownVariants} of ${variants}`} variants`;
  ui.empty.hidden = shown > 0;
}

function toggle(choice, on) {
  state.selected = state.selected.filter((c) => !(c.path === choice.path && c.variant === choice.variant));
  if (on) state.selected.push(choice);
  if (state.selected.length > 2) state.selected.shift();  // the oldest choice makes room
  updateSelection();
}

function updateSelection() {
  const keys = new Set(state.selected.map((c) => choiceKey(c.path, c.variant)));
  for (const [path, article] of state.cards) {
    for (const box of article.querySelectorAll('.select')) box.checked = keys.has(box.dataset.key);
    article.classList.toggle('selected', state.selected.some((c) => c.path === path));
  }
  const [a, b] = state.selected;
  const ready = state.selected.length === 2;
  // Side by side, or the second's edges over the first.
  for (const [link, layout] of [[ui.compare, null], [ui.overlay, 'edges']]) {
    link.classList.toggle('disabled', !ready);
    link.setAttribute('aria-disabled', String(!ready));
    if (ready) link.href = viewerUrl(a.path, { variant: a.variant, compare: b.path, compareVariant: b.variant, layout });
    else link.removeAttribute('href');
  }
  ui.selection.textContent = ready ? `${choiceName(a)} and ${choiceName(b)}` : a ? `${choiceName(a)}: select one more` : 'select two to compare';
}

async function poll() {
  try {
    const response = await fetch('/index.json', { cache: 'no-store' });
    if (!response.ok) throw new Error(`/index.json: ${response.status} ${response.statusText}`);
    const index = await response.json();
    if (index.format !== 'dynpm-catalogue' || !(index.version <= 1)) throw new Error('/index.json: not a dynpm catalogue of version 1');
    const text = JSON.stringify([index.entries, index.problems]);
    if (text !== state.text) {
      state.index = index;
      state.text = text;
      render();
    }
    ui.error.hidden = true;
  } catch (e) {
    ui.error.textContent = String(e.message ?? e);
    ui.error.hidden = false;
  }
  state.polls++;
  setTimeout(poll, pollMs);
}

for (const input of [ui.filter, ui.field, ui.part]) input.addEventListener('input', applyFilter);
ui.clear.addEventListener('click', () => ((state.selected = []), updateSelection()));

// The tests' and scripts' view of the page.
window.dynpmCatalogue = {
  polls: () => state.polls,
  entries: () => (state.index?.entries ?? []).map((e) => e.path),
  shown: () => (state.index?.entries ?? []).filter((e) => !state.cards.get(e.path).hidden).map((e) => e.path),
  // A file by its path, a family's member as PATH#NAME.
  selected: () => state.selected.map((c) => (c.variant == null ? c.path : `${c.path}#${c.variant}`)),
  compareUrl: () => ui.compare.getAttribute('href'),
  overlayUrl: () => ui.overlay.getAttribute('href'),
};

poll();
