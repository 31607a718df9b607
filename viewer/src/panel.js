// The page around the picture (docs/viewer.md "First moments"): the "loading…" screen that the
// HTML shows from its first paint until the first picture (or an error), and the side panel,
// collapsible, collapsed from the start in a small window so that it never hides the model.
import { element } from './fringe.js';

const $ = (id) => document.getElementById(id);

// A window this small starts with the panel collapsed (CSS pixels).
const SMALL = { width: 720, height: 520 };

export class Panel {
  constructor() {
    this.ui = { panel: $('panel'), toggle: $('panel-toggle'), loading: $('loading-screen'), loadingText: $('loading-text') };
    this.ui.toggle.addEventListener('click', () => this.setCollapsed(!this.collapsed));
    this.setCollapsed(window.innerWidth < SMALL.width || window.innerHeight < SMALL.height);
  }

  get collapsed() {
    return this.ui.panel.classList.contains('collapsed');
  }

  setCollapsed(on) {
    this.ui.panel.classList.toggle('collapsed', on);
    this.ui.toggle.setAttribute('aria-expanded', String(!on));
    this.ui.toggle.textContent = on ? '☰' : '‹';
    this.ui.toggle.title = on ? 'Show the panel' : 'Hide the panel';
    this.onToggle?.(on);  // compare lays its canvases out beside the open panel (viewer.js)
  }

  // What the loading screen says while the page starts (the file's name once known).
  loading(text) {
    this.ui.loadingText.textContent = text;
  }

  // The first picture is up (or loading failed): the loading screen goes.
  loaded() {
    this.ui.loading.hidden = true;
  }
}

// A control added to the panel (compare's), above the colour list: a labelled list of
// `choices` (value → text); returns {select, value, set(v)}, set refusing a value not offered.
// changed(v) hears of the panel's changes.
export function panelChoice(id, text, choices, title, changed) {
  const select = element('select', {});
  Object.assign(select, { id, title });
  for (const [value, label] of Object.entries(choices)) select.add(new Option(label, value));
  const label = element('label', {}, text);
  label.htmlFor = id;
  document.getElementById('colour').closest('.row').before(element('div', { className: 'row' }, label, select));
  select.addEventListener('change', () => changed(select.value));
  return {
    select,
    get value() {
      return select.value;
    },
    set(v) {
      if (!Object.hasOwn(choices, v)) throw new RangeError(`${text.toLowerCase()} ${JSON.stringify(String(v))}: one of ${Object.keys(choices).join(', ')}`);
      select.value = v;
    },
  };
}
