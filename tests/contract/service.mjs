// Starts `rollgap serve` on a loopback port chosen by the OS, and stops it (shared by the
// contract scripts). The binary's path is the first argument of the scripts.
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export async function startService(binary, extraArgs = []) {
  // A job store of its own, removed at stop: no run sees another's jobs.
  const dataDir = mkdtempSync(join(tmpdir(), 'rollgap-contract-'));
  const child = spawn(binary, ['serve', '--bind', '127.0.0.1', '--port', '0', '--workers', '2',
    '--data-dir', dataDir, ...extraArgs], {
    stdio: ['ignore', 'ignore', 'pipe'],
  });
  let log = '';
  const port = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no listening line within 20 s:\n${log}`)), 20000);
    child.stderr.on('data', (chunk) => {
      log += chunk;
      const match = /address=127\.0\.0\.1:(\d+)/.exec(log);
      if (match) {
        clearTimeout(timer);
        resolve(Number(match[1]));
      }
    });
    child.on('exit', (code) => reject(new Error(`rollgap serve exited with ${code}:\n${log}`)));
  });
  child.stderr.resume();
  return {
    base: `http://127.0.0.1:${port}`,
    async stop() {
      if (child.exitCode === null) {
        const exited = new Promise((resolve) => child.on('exit', resolve));
        child.kill('SIGTERM');
        const timer = setTimeout(() => child.kill('SIGKILL'), 30000);
        await exited;
        clearTimeout(timer);
      }
      rmSync(dataDir, { recursive: true, force: true });
    },
  };
}

export function toolsDir() {
  const dir = process.env.ROLLGAP_NODE_TOOLS || '/var/cache/rollgap/node-tools';
  return `${dir}/node_modules`;
}
