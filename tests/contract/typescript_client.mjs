// Contract test: openapi-typescript (default options) turns the served /openapi.json into types
// and tsc (strict) type-checks client.ts (answers) and requests.ts (requests) against them.
// usage: node typescript_client.mjs path/to/rollgap
import { execFileSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { startService, toolsDir } from './service.mjs';

const binary = process.argv[2];
if (!binary) throw new Error('usage: node typescript_client.mjs path/to/rollgap');
const here = dirname(fileURLToPath(import.meta.url));
const bin = join(toolsDir(), '.bin');
const work = mkdtempSync(join(tmpdir(), 'rollgap-ts-'));
const service = await startService(binary);
try {
  const document = await (await fetch(`${service.base}/openapi.json`)).text();
  writeFileSync(join(work, 'openapi.json'), document);
} finally {
  await service.stop();
}
try {
  execFileSync(join(bin, 'openapi-typescript'), [join(work, 'openapi.json'), '-o', join(work, 'rollgap-api.d.ts')], {
    stdio: 'inherit',
  });
  copyFileSync(join(here, 'client.ts'), join(work, 'client.ts'));
  copyFileSync(join(here, 'requests.ts'), join(work, 'requests.ts'));
  execFileSync(join(bin, 'tsc'), ['--noEmit', '--strict', '--target', 'es2022', '--module', 'es2022',
    '--moduleResolution', 'bundler', join(work, 'client.ts'), join(work, 'requests.ts')], { stdio: 'inherit' });
  console.log('client.ts (answers) and requests.ts (partial patches, a sweep, a job, a batch) type-check against the types generated from the served document');
} finally {
  rmSync(work, { recursive: true, force: true });
}
