// The messages a real server sent (fixtures/server_messages.jsonl), and the terms its hello states,
// which the client's checks of its own messages take.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { parseServerMessage, type HelloMessage } from '../src/protocol/messages';
import { termsOf, type ServerTerms } from './client_checks';
import { tfTerms, type TfTerms } from '../src/panels/tf_model';

/** hello, volumes, opened, ack, stats, error, state: each one line of JSON text. */
export const recordedMessages = readFileSync(
  path.join(__dirname, 'fixtures/server_messages.jsonl'),
  'utf8',
)
  .split('\n')
  .filter((line) => line.trim() !== '');

export const recordedHello = parseServerMessage(recordedMessages[0]!) as HelloMessage;

/** The settings' ranges the server announced (protocol_test holds them against the C++ table). */
export const recordedRanges = recordedHello.ranges;

/** Its ranges, limits and preset names, with any mode name. */
export const recordedTerms: ServerTerms = { ...termsOf(recordedHello), modes: null };

/** Its presets, nominal CT range and point limit, as the transfer-function model takes them. */
export const recordedTfTerms: TfTerms = tfTerms(recordedHello);
