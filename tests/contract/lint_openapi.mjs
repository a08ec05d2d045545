// Contract test: @redocly/cli lint of the served /openapi.json (recommended rules); any warning
// or error fails.
// usage: node lint_openapi.mjs path/to/rollgap
import { execFileSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { startService, toolsDir } from './service.mjs';

const binary = process.argv[2];
if (!binary) throw new Error('usage: node lint_openapi.mjs path/to/rollgap');
const work = mkdtempSync(join(tmpdir(), 'rollgap-lint-'));
const service = await startService(binary);
let size = 0;
try {
  const document = await (await fetch(`${service.base}/openapi.json`)).text();
  size = Buffer.byteLength(document);
  writeFileSync(join(work, 'openapi.json'), document);
} finally {
  await service.stop();
}
try {
  const output = execFileSync(join(toolsDir(), '.bin', 'redocly'),
    ['lint', '--format', 'stylish', '--max-problems', '200', join(work, 'openapi.json')],
    { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'], env: { ...process.env, REDOCLY_TELEMETRY: 'off', REDOCLY_SUPPRESS_UPDATE_NOTICE: 'true' } });
  if (/warning|error/i.test(output)) {
    console.error(output);
    process.exit(1);
  }
  console.log(`served /openapi.json (${size} bytes) lints clean`);
} catch (error) {
  console.error(error.stdout || '', error.stderr || '');
  process.exit(1);
} finally {
  rmSync(work, { recursive: true, force: true });
}
