// What reading a server message checks a value against, each failure a ProtocolError naming the
// member (as a JSON pointer) and what it should have been. No DOM here.

/** Thrown when a server message does not have the shape protocol v1 promises. */
export class ProtocolError extends Error {
  constructor(
    message: string,
    readonly field: string,
  ) {
    super(`${message} (at ${field || '/'})`);
    this.name = 'ProtocolError';
  }
}

/**
 * Thrown for a message type this client does not know. Within v1 the server may add message types
 * that answer no request (§3), so a client ignores them rather than report a problem.
 */
export class UnknownMessageType extends ProtocolError {
  constructor(readonly type: string) {
    super(`unknown message type "${type}"`, '/type');
    this.name = 'UnknownMessageType';
  }
}

export function isObject(value: unknown): value is Record<string, unknown> {
  return typeof value === 'object' && value !== null && !Array.isArray(value);
}

export function need<T>(ok: boolean, value: T, what: string, field: string): T {
  if (!ok) {
    throw new ProtocolError(`expected ${what}`, field);
  }
  return value;
}

export function str(o: Record<string, unknown>, key: string, at: string): string {
  const v = o[key];
  return need(typeof v === 'string', v as string, 'a string', `${at}/${key}`);
}

export function num(o: Record<string, unknown>, key: string, at: string): number {
  const v = o[key];
  return need(typeof v === 'number' && Number.isFinite(v), v as number, 'a number', `${at}/${key}`);
}

export function bool(o: Record<string, unknown>, key: string, at: string): boolean {
  const v = o[key];
  return need(typeof v === 'boolean', v as boolean, 'a boolean', `${at}/${key}`);
}

export function oneOf<T extends string>(v: unknown, names: readonly T[], field: string): T {
  const ok = typeof v === 'string' && (names as readonly string[]).includes(v);
  return need(ok, v as T, `one of ${names.join(', ')}`, field);
}

export function obj(o: Record<string, unknown>, key: string, at: string): Record<string, unknown> {
  const v = o[key];
  return need(isObject(v), v as Record<string, unknown>, 'an object', `${at}/${key}`);
}

export function numbers(
  o: Record<string, unknown>,
  key: string,
  at: string,
  length?: number,
): number[] {
  const v = o[key];
  const ok =
    Array.isArray(v) &&
    (length === undefined || v.length === length) &&
    v.every((x) => typeof x === 'number' && Number.isFinite(x));
  return need(ok, v as number[], length ? `${length} numbers` : 'numbers', `${at}/${key}`);
}

export function optionalId(o: Record<string, unknown>): number | undefined {
  if (o['id'] === undefined) {
    return undefined;
  }
  return need(Number.isInteger(o['id']), o['id'] as number, 'an integer', '/id');
}
