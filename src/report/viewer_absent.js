// The viewer's stand-in in a library-only build (-DPOLYAXIS_VIEWER=OFF, no Node.js): report.html
// still carries the plan's data and says why there is no 3-D view.
(function () {
  const note = document.createElement('p');
  note.id = 'viewer-absent';
  note.textContent = 'This polyaxis was built without the 3-D viewer (-DPOLYAXIS_VIEWER=OFF): ' +
    'the plan\'s data is in this page, plan.json and report.json; a build with the viewer draws it.';
  document.body.prepend(note);
})();
