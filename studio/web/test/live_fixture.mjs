// The live fixture server and a browser, started before a test file's tests and closed after
// them: `const live = liveFixture();` then `live.server`, `live.browser` inside the tests.
import { before, after } from 'node:test';
import { startFixtureServer } from './fixture_server.mjs';
import { launch } from './browser.mjs';

export function liveFixture() {
  const live = {};
  before(async () => {
    live.server = await startFixtureServer('live');
    live.browser = await launch();
  });
  after(async () => {
    await live.browser?.close();
    await live.server?.close();
  });
  return live;
}
