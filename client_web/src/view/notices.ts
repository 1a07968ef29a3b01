// Messages for people: a banner for the connection (connecting, server not reachable, connection
// lost and reconnecting), and notices for server errors and other events, which fade after a while.

import type { ConnectionStatus } from '../protocol/connection';

export type NoticeKind = 'error' | 'warning' | 'info';

export class Notices {
  private readonly banner: HTMLElement;
  private readonly bannerText: HTMLElement;
  private readonly retryButton: HTMLButtonElement;
  private readonly list: HTMLElement;
  private countdown: ReturnType<typeof setInterval> | null = null;

  constructor(parent: HTMLElement, retry: () => void) {
    this.banner = document.createElement('div');
    this.banner.className = 'connection-banner';
    this.banner.setAttribute('role', 'status');
    this.banner.hidden = true;
    this.bannerText = document.createElement('span');
    this.retryButton = document.createElement('button');
    this.retryButton.textContent = 'Retry now';
    this.retryButton.addEventListener('click', retry);
    this.banner.append(this.bannerText, this.retryButton);
    this.list = document.createElement('div');
    this.list.className = 'notices';
    this.list.setAttribute('role', 'log');
    this.list.setAttribute('aria-live', 'polite');
    parent.append(this.banner, this.list);
  }

  /** Shows the connection's state in the banner (hidden once connected). */
  connection(status: ConnectionStatus, url: string): void {
    if (this.countdown !== null) clearInterval(this.countdown);
    this.countdown = null;
    this.banner.dataset['state'] = status.kind;
    this.retryButton.hidden = true;
    switch (status.kind) {
      case 'connected':
        this.banner.hidden = true;
        return;
      case 'closed':
        this.banner.hidden = false;
        this.bannerText.textContent = 'Disconnected.';
        return;
      case 'connecting':
        this.banner.hidden = false;
        this.bannerText.textContent =
          status.attempt > 1
            ? `Reconnecting to ${url} (attempt ${status.attempt})…`
            : `Connecting to ${url}…`;
        return;
      case 'lost':
      case 'unreachable': {
        this.banner.hidden = false;
        this.retryButton.hidden = false;
        const until = performance.now() + status.retryInMs;
        const text = (): string => {
          const seconds = Math.max(0, Math.ceil((until - performance.now()) / 1000));
          return status.kind === 'lost'
            ? `Connection to the server lost (${status.reason}). Reconnecting in ${seconds} s; the session will be restored.`
            : `The Penumbra server at ${url} is not reachable (${status.reason}). Retrying in ${seconds} s.`;
        };
        this.bannerText.textContent = text();
        this.countdown = setInterval(() => (this.bannerText.textContent = text()), 500);
        return;
      }
    }
  }

  /** Adds a notice; errors stay 12 s, others 5 s, or until closed. */
  show(kind: NoticeKind, title: string, detail = ''): HTMLElement {
    const item = document.createElement('div');
    item.className = `notice ${kind}`;
    const head = document.createElement('strong');
    head.textContent = title;
    const body = document.createElement('span');
    body.textContent = detail;
    const close = document.createElement('button');
    close.className = 'close';
    close.textContent = '×';
    close.setAttribute('aria-label', 'dismiss');
    close.addEventListener('click', () => item.remove());
    item.append(close, head, body);
    this.list.prepend(item);
    while (this.list.children.length > 5) this.list.lastElementChild?.remove();
    setTimeout(() => item.remove(), kind === 'error' ? 12000 : 5000);
    return item;
  }
}
