// Just enough of the DOM for the panels and overlays built of plain elements, so their tests run
// in Node: elements hold their children, attributes and listeners; nothing is laid out.
import { vi } from 'vitest';

export class FakeElement extends EventTarget {
  className = '';
  textContent = '';
  title = '';
  type = '';
  value = '';
  placeholder = '';
  min = '';
  max = '';
  step = '';
  hidden = false;
  disabled = false;
  checked = false;
  scrollTop = 0;
  readonly clientWidth = 800;
  readonly clientHeight = 600;
  readonly offsetWidth = 0;
  readonly offsetHeight = 0;
  readonly offsetTop = 0;
  readonly dataset: Record<string, string> = {};
  readonly style: Record<string, string> = {};
  readonly attributes = new Map<string, string>();
  readonly classes = new Set<string>();
  readonly classList = {
    add: (name: string) => this.classes.add(name),
    contains: (name: string) => this.classes.has(name),
    toggle: (name: string, on?: boolean) => {
      const add = on ?? !this.classes.has(name);
      if (add) this.classes.add(name);
      else this.classes.delete(name);
      return add;
    },
  };
  children: FakeElement[] = [];

  constructor(readonly tagName: string) {
    super();
  }

  setAttribute(name: string, value: string): void {
    this.attributes.set(name, value);
  }
  append(...children: FakeElement[]): void {
    this.children.push(...children);
  }
  appendChild(child: FakeElement): FakeElement {
    this.children.push(child);
    return child;
  }
  replaceChildren(...children: FakeElement[]): void {
    this.children = children;
  }
  getBoundingClientRect() {
    return { left: 0, top: 0, width: this.clientWidth, height: this.clientHeight };
  }
  closest(): null {
    return null;
  }
}

/** Puts the fake document (with Option and ResizeObserver) in place of the browser's. */
export function useFakeDom(): void {
  vi.stubGlobal('document', {
    createElement: (tag: string) => new FakeElement(tag),
    createElementNS: (_ns: string, tag: string) => new FakeElement(tag),
    createDocumentFragment: () => new FakeElement('#fragment'),
  });
  vi.stubGlobal(
    'Option',
    class extends FakeElement {
      constructor(text: string, value: string) {
        super('option');
        this.textContent = text;
        this.value = value;
      }
    },
  );
  vi.stubGlobal(
    'ResizeObserver',
    class {
      observe(): void {}
    },
  );
}
