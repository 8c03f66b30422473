// The surgeon's input buttons: pressing one sends the input to the server (POST /api/input),
// whose answer the page then shows (the fixture's 'needle' chart advances).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startFixtureServer } from './fixture_server.mjs';
import { launch, openStudio } from './browser.mjs';

let server;
let browser;
before(async () => {
  server = await startFixtureServer('live');
  browser = await launch();
});
after(async () => {
  await browser?.close();
  await server?.close();
});

test('one button per model input, labelled from the model; the title names the run', async (t) => {
  const { page } = await openStudio(browser, server.pageUrl, t);
  assert.deepEqual(await page.locator('#inputs button').allInnerTexts(), ['Needle mounted', 'Cryo cycle done']);
  assert.equal(await page.title(), 'fixture / synthetic_arm · cobra studio');
});

test('pressing "Needle mounted" sends the input and the needle chart advances', async (t) => {
  const { page } = await openStudio(browser, server.pageUrl, t);
  assert.match(await page.locator('#charts tr[data-key="needle"]').innerText(), /WaitMounted/);
  assert.deepEqual(server.inputs, []);
  await page.getByRole('button', { name: 'Needle mounted' }).click();
  await page.waitForFunction(() => document.querySelector('#charts tr[data-key="needle"]').innerText.includes('Mounted')
    && !document.querySelector('#charts tr[data-key="needle"]').innerText.includes('Wait'), null, { timeout: 10000 });
  assert.deepEqual(server.inputs, ['needle_mounted']);
  await page.locator('#events li', { hasText: 'needle: e_needle_mounted' }).waitFor();
});
