// Starting cobra for the end-to-end tests (COBRA_BIN, set by CTest): a live or replay server
// that prints its studio line, or a run to its end with its output and exit status.
import { spawn } from 'node:child_process';

const { COBRA_BIN } = process.env;
const started = [];

/**
 * Starts `cobra ARGS`; resolves to { url, child, stdout(), stderr() } once it printed its studio
 * line, `studio: URL` (`editor: URL` with label 'editor', as `cobra edit` prints it; stdout(),
 * stderr(): what it wrote on each so far).
 */
export function startCobra(args, label = 'studio') {
  const child = spawn(COBRA_BIN, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  started.push(child);
  let output = '';
  let out = '';
  let errors = '';
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`cobra ${args.join(' ')}: no ${label} line in 60 s; output:\n${output}`)), 60000);
    const read = (chunk) => {
      output += chunk;
      const m = new RegExp(`^${label}: (http:\\/\\/\\S+)$`, 'm').exec(output);
      if (m) {
        clearTimeout(timer);
        resolve({ url: m[1], child, stdout: () => out, stderr: () => errors });
      }
    };
    child.stdout.on('data', (chunk) => {
      out += chunk;
      read(chunk);
    });
    child.stderr.on('data', (chunk) => {
      errors += chunk;
      read(chunk);
    });
    child.on('exit', (code) => reject(new Error(`cobra ${args.join(' ')} exited with ${code} before its ${label} line:\n${output}`)));
  });
}

/** Runs `cobra ARGS` to its end: resolves to { status, stdout, stderr }. */
export function runCobra(args) {
  return new Promise((resolve) => {
    const child = spawn(COBRA_BIN, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    let stdout = '';
    let stderr = '';
    child.stdout.on('data', (c) => { stdout += c; });
    child.stderr.on('data', (c) => { stderr += c; });
    child.on('exit', (status) => resolve({ status, stdout, stderr }));
  });
}

/** Kills every cobra startCobra started that still runs (the servers serve until killed). */
export function stopCobras() {
  for (const child of started) if (child.exitCode === null) child.kill('SIGKILL');
}
