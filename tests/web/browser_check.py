#!/usr/bin/python3
"""Drives the web front end in headless Chromium (Debian chromium + chromium-driver, python3-selenium):
logs in as an operator, sees a live value change without reloading, operates, logs out; logs in as
a viewer and is refused the same operation; no Content-Security-Policy violation on any page.

usage: browser_check.py URL SCREENSHOT_DIR   (users op/operator-pass-1 and viewer/viewer-pass-1)
Exit 0 on success; otherwise the reason on stderr (also when Chromium cannot start)."""
import os
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support import expected_conditions as EC
from selenium.webdriver.support.ui import WebDriverWait

URL, SHOTS = sys.argv[1].rstrip('/'), sys.argv[2]
MACHINE = os.environ.get('TRUEAXIS_BROWSER_MACHINE', 'm0004')


def fail(msg):
    print('browser check FAILED: ' + msg, file=sys.stderr)
    sys.exit(1)


def start():
    opts = webdriver.ChromeOptions()
    opts.binary_location = '/usr/bin/chromium'
    for a in ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
              '--disable-background-networking', '--disable-component-update', '--disable-sync',
              '--disable-dev-shm-usage', '--window-size=1400,1000',
              '--user-data-dir=' + tempfile.mkdtemp(prefix='trueaxis-chromium-')]:
        opts.add_argument(a)
    opts.set_capability('goog:loggingPrefs', {'browser': 'ALL'})
    try:
        return webdriver.Chrome(service=Service('/usr/bin/chromedriver'), options=opts)
    except Exception as e:  # noqa: BLE001 - the reason is the message
        fail('Chromium could not start: %s' % e)


def text(d, css):
    return d.find_element(By.CSS_SELECTOR, css).text


def login(d, user, password):
    d.get(URL + '/login.html')
    d.find_element(By.ID, 'user').send_keys(user)
    d.find_element(By.ID, 'password').send_keys(password)
    d.find_element(By.ID, 'login').click()
    WebDriverWait(d, 10).until(EC.url_contains('/overview.html'))
    WebDriverWait(d, 10).until(lambda d: len(d.find_elements(By.CSS_SELECTOR, '#machines tbody tr')) > 0)
    who = text(d, '#who')
    if user not in who:
        fail('logged in as %s but the page says %r' % (user, who))


def logout(d):
    d.find_element(By.ID, 'logout').click()
    WebDriverWait(d, 10).until(EC.url_contains('/login.html'))
    d.get(URL + '/overview.html')  # the session is gone: the page's API call is refused → login
    WebDriverWait(d, 10).until(EC.url_contains('/login.html'))


def open_machine(d):
    d.get(URL + '/machine.html?id=' + MACHINE)
    WebDriverWait(d, 10).until(lambda d: text(d, '#live-seq').strip().isdigit())
    WebDriverWait(d, 10).until(lambda d: len(d.find_elements(By.ID, 'temp-spindle')) == 1)


def wait_status(d, words):
    WebDriverWait(d, 10).until(lambda d: any(w in text(d, '#status') for w in words))
    return text(d, '#status')


def csp_violations(d):
    try:
        logs = d.get_log('browser')
    except Exception:  # noqa: BLE001 - some drivers have no log
        return []
    return [l['message'] for l in logs
            if l.get('source') == 'security' or 'Content Security Policy' in l['message'] or 'Refused to' in l['message']]


d = start()
try:
    # Operator: log in, see the overview, watch a live value change, operate.
    login(d, 'op', 'operator-pass-1')
    d.save_screenshot(os.path.join(SHOTS, 'web_overview.png'))
    open_machine(d)
    seq0, temp0 = int(text(d, '#live-seq')), text(d, '#temp-spindle')
    url0 = d.current_url
    try:
        WebDriverWait(d, 10).until(lambda d: int(text(d, '#live-seq')) > seq0 and text(d, '#temp-spindle') != temp0)
    except Exception:  # noqa: BLE001
        fail('no live change in 10 s (sequence %d, spindle %s)' % (seq0, temp0))
    if d.current_url != url0:
        fail('the page reloaded')
    points = d.execute_script('return Chart.getChart("live-temp").data.datasets[0].data.length')
    if points < 2:
        fail('the live chart has %d points' % points)
    if text(d, '#axis-X-state') != 'on':
        fail('axis X should start enabled')
    if text(d, '#axis-X-model') != 'model':
        fail('axis X should show the model with its own sensors, not %r' % text(d, '#axis-X-model'))
    d.find_element(By.ID, 'axis-X-toggle').click()
    status = wait_status(d, ['done', 'refused'])
    if 'done' not in status:
        fail('operator could not disable X: ' + status)
    WebDriverWait(d, 10).until(lambda d: text(d, '#axis-X-state') == 'off')
    time.sleep(1.5)  # a few more live points for the screenshot
    d.set_window_size(1400, 1900)
    d.save_screenshot(os.path.join(SHOTS, 'web_machine.png'))
    d.set_window_size(1400, 1000)
    bad = csp_violations(d)
    if bad:
        fail('Content-Security-Policy violations: %s' % bad)
    logout(d)

    # Viewer: the same operation is refused by the server.
    login(d, 'viewer', 'viewer-pass-1')
    open_machine(d)
    d.find_element(By.ID, 'axis-Y-toggle').click()
    status = wait_status(d, ['done', 'refused'])
    if 'refused' not in status or 'operator' not in status:
        fail('a viewer should be refused, the page says: ' + status)
    time.sleep(0.5)
    if text(d, '#axis-Y-state') != 'on':
        fail('the refused operation took effect')
    logout(d)
    print('browser check passed: live values changed after sequence %d, operator disabled X, viewer refused' % seq0)
finally:
    d.quit()
