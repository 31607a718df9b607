// dynpm serve's catalogue page (catalogue.html): the folder's .dpm files from /index.json (the
// entries `dynpm catalogue` writes, docs/batch.md), each with its thumbnail and metadata; a
// filter by name or source, field and part; one opens in the viewer (/view?model=…), two
// selected open side by side (/view?model=…&compare=…). The page asks for /index.json again
// every few seconds (?poll=MS), so files that a running batch finishes appear by themselves.
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
  selected: [],  // paths, at most two, the first chosen first
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
// by its name (&variant=, docs/batch.md).
export function viewerUrl(path, { compare, variant } = {}) {
  const q = new URLSearchParams({ model: fileUrl(path) });
  if (compare) q.set('compare', fileUrl(compare));
  if (variant) q.set('variant', variant);
  return `/view?${q}`;
}

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
// A family file's members (a VARI chunk; docs/FORMAT.md): names, or objects with a name.
const variantsOf = (entry) => (Array.isArray(entry.variants) ? entry.variants.map((v) => (typeof v === 'string' ? v : String(v?.name ?? ''))) : []);

function card(entry) {
  const path = entry.path;
  const picture = entry.thumbnail
    ? element('img', { class: 'thumb', src: thumbUrl(path), alt: `${entry.name}, last step`, loading: 'lazy' })
    : element('div', { class: 'thumb placeholder', text: 'no thumbnail' });
  const open = element('a', { href: viewerUrl(path), class: 'open', text: entry.name });
  const times = entry.steps > 1 ? ` (t ${time(entry.first_time)} … ${time(entry.last_time)})` : '';
  const fields = entry.fields.length ? entry.fields.map((f) => `${f.name}${f.unit ? ` [${f.unit}]` : ''} (${f.location})`).join(', ') : 'none';
  const parts = entry.parts.length <= 6 ? entry.parts.map(partName).join(', ') : `${entry.parts.length} parts`;
  const select = element('input', { type: 'checkbox', class: 'select', 'aria-label': `select ${entry.name} to compare` });
  select.checked = state.selected.includes(path);
  select.addEventListener('change', () => toggle(path, select.checked));
  const variants = variantsOf(entry);
  const article = element(
    'article',
    { class: 'entry', 'data-path': path },
    element('a', { href: viewerUrl(path), tabindex: '-1' }, picture),
    element('h2', {}, open),
    element('p', { class: 'facts muted', text: path + (entry.source ? ` · from ${entry.source}` : '') }),
    element('p', { class: 'facts', text: `${int(entry.vertices)} nodes · ${int(entry.faces)} faces · ${int(entry.steps)} steps${times}` }),
    element('p', { class: 'facts', text: `fields: ${fields}` }),
    element('p', { class: 'facts', text: `parts: ${parts}` }),
    element('p', { class: 'facts muted', text: `${bytesText(entry.bytes)} · built ${entry.built.replace('T', ' ').replace('Z', ' UTC')}` }),
    variants.length
      ? element('ul', { class: 'variants' }, ...variants.map((v) => element('li', {}, element('a', { href: viewerUrl(path, { variant: v }), text: v }))))
      : null,
    element('label', { class: 'row muted' }, select, 'select to compare'),
  );
  article.classList.toggle('selected', select.checked);
  return article;
}

function matches(entry) {
  const text = ui.filter.value.trim().toLowerCase();
  if (text && ![entry.name, entry.path, entry.source].some((s) => String(s).toLowerCase().includes(text))) return false;
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
  state.selected = state.selected.filter((p) => state.cards.has(p));
  ui.entries.replaceChildren(...state.cards.values());
  ui.problems.replaceChildren(...problems.map((p) => element('li', { text: `cannot read ${p}` })));
  ui.problems.hidden = problems.length === 0;
  applyFilter();
  updateSelection();
}

function applyFilter() {
  const entries = state.index?.entries ?? [];
  let shown = 0;
  for (const e of entries) {
    const visible = matches(e);
    state.cards.get(e.path).hidden = !visible;
    shown += visible;
  }
  ui.count.textContent = shown === entries.length ? `${entries.length} files` : `${shown} of ${entries.length} files`;
  ui.empty.hidden = shown > 0;
}

function toggle(path, on) {
  state.selected = state.selected.filter((p) => p !== path);
  if (on) state.selected.push(path);
  if (state.selected.length > 2) state.selected.shift();  // the oldest choice makes room
  updateSelection();
}

function updateSelection() {
  for (const [path, article] of state.cards) {
    const on = state.selected.includes(path);
    article.classList.toggle('selected', on);
    article.querySelector('.select').checked = on;
  }
  const [a, b] = state.selected;
  const ready = state.selected.length === 2;
  ui.compare.classList.toggle('disabled', !ready);
  ui.compare.setAttribute('aria-disabled', String(!ready));
  if (ready) ui.compare.href = viewerUrl(a, { compare: b });
  else ui.compare.removeAttribute('href');
  const name = (p) => p.replace(/\.dpm$/, '');
  ui.selection.textContent = ready ? `${name(a)} and ${name(b)}` : a ? `${name(a)}: select one more` : 'select two to compare';
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
  selected: () => [...state.selected],
  compareUrl: () => ui.compare.getAttribute('href'),
};

poll();
