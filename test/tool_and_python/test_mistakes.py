"""doc/mistakes.md shows what a user is told today: tools/mistakes.py makes each mistake once (through cv2 and the
tool) and every row it prints must stand in the doc as printed. A message that changes, or a mistake that passes in
silence, fails its row here."""
import os
import subprocess
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class MistakesTable(unittest.TestCase):

    def test_every_row_as_printed(self):
        tool = os.environ.get('LIDARSGM_TOOL')
        if not tool:
            raise unittest.SkipTest('LIDARSGM_TOOL is not set')
        out = subprocess.run([sys.executable, os.path.join('tools', 'mistakes.py'), '--tool', tool], cwd=ROOT,
                             capture_output=True, text=True, timeout=600)
        self.assertEqual(out.returncode, 0, out.stderr)
        rows = [ln for ln in out.stdout.splitlines() if ln.startswith('| ') and not ln.startswith('| mistake')
                and not ln.startswith('| ---')]
        self.assertGreaterEqual(len(rows), 15, out.stdout)
        with open(os.path.join(ROOT, 'doc', 'mistakes.md')) as f:
            doc = f.read()
        for row in rows:
            with self.subTest(row=row.split(' | ')[0]):
                self.assertNotIn('(nothing raised)', row)
                self.assertNotIn('(nothing said)', row)
                self.assertNotIn('in function', row)
                self.assertIn(row, doc, 'doc/mistakes.md lacks this row as printed now (rerun tools/mistakes.py)')


if __name__ == '__main__':
    unittest.main()
