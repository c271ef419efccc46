'use strict';
document.getElementById('login-form').addEventListener('submit', async (ev) => {
  ev.preventDefault();
  try {
    await TA.api('POST', '/api/login', {
      user: document.getElementById('user').value,
      password: document.getElementById('password').value,
    });
    location.href = '/overview.html';
  } catch (e) {
    TA.status(e.message, true);
  }
});
