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

/**
 * What a real server sent of label maps (fixtures/label_messages.jsonl), AAL drawn over ch2: the
 * labels answering add_labels, the labels a viewer got after joined (no id), the ack of a set with
 * a labels patch (only 45, 46, 57; 46 half opaque; blend 0.8) and the state the viewer got of it, a
 * pick that hit a label, one that hit nothing, and the labels answering remove_labels.
 */
export const recordedLabelMessages = readFileSync(
  path.join(__dirname, 'fixtures/label_messages.jsonl'),
  'utf8',
)
  .split('\n')
  .filter((line) => line.trim() !== '');
