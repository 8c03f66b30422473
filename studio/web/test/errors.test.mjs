// Errors reach the page as a visible message: /api/model answering 500 { error }, a WebSocket
// the server closes, an error message on the WebSocket; a 503 (the run is still loading) is no error: the page asks again.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startFixtureServer, MODEL_ERROR, WS_ERROR } from './fixture_server.mjs';
import { launch, openStudio } from './browser.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

async function bannerOf(mode, query) {
  const server = await startFixtureServer(mode);
  try {
    const page = await browser.newPage();
    await page.goto(server.url + query);
    const banner = page.locator('#error');
    await banner.waitFor({ state: 'visible', timeout: 15000 });
    return await banner.innerText();
  } finally {
    await server.close();
  }
}

test('a 500 from /api/model (the run could not start) shows the line cobra printed: cobra: and the error text', async () => {
  const text = await bannerOf('error', '?token=0123456789abcdef0123456789abcdef');
  assert.equal(text, `cobra: ${MODEL_ERROR}`);
});

test('a WebSocket closed by the server shows that the view stopped', async () => {
  const text = await bannerOf('drop', '?token=0123456789abcdef0123456789abcdef');
  assert.match(text, /^\/ws: the connection to the cobra server closed \(code 1011: fixture server dropped the connection\); the view is stopped$/);
});

test('an error message on the WebSocket shows its text', async () => {
  const text = await bannerOf('wserror', '?token=0123456789abcdef0123456789abcdef');
  assert.equal(text, `/ws: ${WS_ERROR}`);
});

test('a 503 from /api/model (the run is loading) is asked again until the model comes', async (t) => {
  const server = await startFixtureServer('loading');
  try {
    const { page, errors } = await openStudio(browser, server.pageUrl, t);
    assert.equal(server.modelRequestsLeftLoading(), 0);
    assert.equal(await page.locator('#error').isHidden(), true);
    assert.deepEqual(errors, []);
  } finally {
    await server.close();
  }
});
