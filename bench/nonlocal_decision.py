#!/usr/bin/python3
"""The non-local patch stage of cloud denoising and its check, on harness cloud cases (issue 37).

usage: /usr/bin/python3 bench/nonlocal_decision.py CASE_DIR... [--k 0.5 1] [--forced]
           [--tool build/pcl_patchdict] [--harness ../shared/harness] [--work /tmp/nonlocal_decision]

Each CASE_DIR is a harness case folder (cases.py / cases_extra.py: gt.ply, cloud_noise_<k>.ply). Per
case and noise level k it runs `denoise` three ways — `--no-patches` (the geometric base), the
default (the coupled bootstrap check decides the stage), and with --forced also `--patch-decision
always` — scores each with the harness's `eval.py cloud` (a judge, not a dependency of the project)
and prints: the decision, the check's estimated error ratio (patch_error / base_error, at noise
sigma*sqrt(1 + alpha^2)), the measured RMS ratios default/base and forced/base, and the stage's seconds.
"""
import argparse
import json
import os
import subprocess
import sys


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit('failed (%d): %s\n%s' % (r.returncode, ' '.join(cmd), r.stderr.strip()))
    return r.stdout


def rms(harness, gt, cloud):
    return json.loads(run(['/usr/bin/python3', os.path.join(harness, 'eval.py'), 'cloud', gt, cloud]))['rms']


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('cases', nargs='+')
    ap.add_argument('--k', nargs='+', default=['0.5'])
    ap.add_argument('--forced', action='store_true', help='also --patch-decision always')
    ap.add_argument('--tool', default=os.path.join(here, '..', 'build', 'pcl_patchdict'))
    ap.add_argument('--harness', default=os.path.join(here, '..', '..', 'shared', 'harness'))
    ap.add_argument('--work', default='/tmp/nonlocal_decision')
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    print('| cloud | k | decision | estimate | default / base | forced / base | check s | apply s |')
    print('|---|---|---|---|---|---|---|---|')
    for case in a.cases:
        gt = os.path.join(case, 'gt.ply')
        for k in a.k:
            noisy = os.path.join(case, 'cloud_noise_%s.ply' % k)
            if not os.path.exists(noisy) or not os.path.exists(gt):
                sys.exit('%s: no gt.ply or cloud_noise_%s.ply' % (case, k))
            stem = os.path.join(a.work, '%s_%s' % (os.path.basename(os.path.normpath(case)), k))
            run([a.tool, 'denoise', noisy, '--no-patches', '-o', stem + '_base.ply', '--quiet'])
            report = json.loads(run([a.tool, 'denoise', noisy, '-o', stem + '_default.ply', '--json', '--quiet']))
            stage = report['nonlocal_patches']
            base = rms(a.harness, gt, stem + '_base.ply')
            default = rms(a.harness, gt, stem + '_default.ply') / base
            forced = ''
            if a.forced:
                run([a.tool, 'denoise', noisy, '--patch-decision', 'always', '-o', stem + '_forced.ply', '--quiet'])
                forced = '%.3f' % (rms(a.harness, gt, stem + '_forced.ply') / base)
            estimate = stage['patch_error'] / stage['base_error'] if stage['base_error'] > 0 else float('nan')
            print('| %s | %s | %s | %.3f | %.3f | %s | %.1f | %.1f |' % (
                os.path.basename(os.path.normpath(case)), k, stage['decision'], estimate, default, forced,
                stage['seconds_check'], stage['seconds_apply']), flush=True)


if __name__ == '__main__':
    main()
