// The surgeon's input buttons: pressing one sends the input to the server (POST /api/input),
// whose answer the page then shows (the fixture's 'needle' chart advances).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { openStudio } from './browser.mjs';
import { liveFixture } from './live_fixture.mjs';

const live = liveFixture();

test('one button per model input, labelled from the model; the title names the run', async (t) => {
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  assert.deepEqual(await page.locator('#inputs button').allInnerTexts(), ['Needle mounted', 'Cryo cycle done']);
  assert.equal(await page.title(), 'fixture / synthetic_arm · cobra studio');
});

test('pressing "Needle mounted" sends the input and the needle chart advances', async (t) => {
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  assert.match(await page.locator('#charts tr[data-key="needle"]').innerText(), /WaitMounted/);
  assert.deepEqual(live.server.inputs, []);
  await page.getByRole('button', { name: 'Needle mounted' }).click();
  await page.waitForFunction(() => document.querySelector('#charts tr[data-key="needle"]').innerText.includes('Mounted')
    && !document.querySelector('#charts tr[data-key="needle"]').innerText.includes('Wait'), null, { timeout: 10000 });
  assert.deepEqual(live.server.inputs, ['needle_mounted']);
  await page.locator('#events li', { hasText: 'needle: e_needle_mounted' }).waitFor();
});
