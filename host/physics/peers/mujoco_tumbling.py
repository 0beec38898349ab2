"""The torque-free tumbling box of `vphys accuracy` in MuJoCo: one line of JSON per run.

Usage: mujoco_tumbling.py DT [DT ...]

The box is 0.1 x 0.2 x 0.4 m and 1 kg on a free joint, with no gravity and no contacts.
It starts with omega = (0, 5, 0.05) rad/s in the body frame (MuJoCo's free-joint angular
velocity is in the body frame) and runs for 10 s, with each of MuJoCo's integrators at each
step DT (s). Each line is {"integrator", "dt", "cpu_s", "omega": [[x, y, z], ...]}: the body
angular velocity every 0.1 s, and the CPU time of the stepping. The steps of one 0.1 s
sample run in one mj_step call, so Python's overhead is once per sample.
"""

import json
import sys
import time

import mujoco

XML = """
<mujoco>
  <option gravity="0 0 0" timestep="{dt}" integrator="{integrator}">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body>
      <freejoint/>
      <geom type="box" size="0.05 0.1 0.2" mass="1"/>
    </body>
  </worldbody>
</mujoco>
"""

SAMPLE, DURATION = 0.1, 10.0


def run(integrator, dt):
    model = mujoco.MjModel.from_xml_string(XML.format(dt=dt, integrator=integrator))
    data = mujoco.MjData(model)
    data.qvel[3:6] = [0.0, 5.0, 0.05]
    per_sample = round(SAMPLE / dt)
    omega, cpu = [], 0.0
    for _ in range(round(DURATION / SAMPLE)):
        t0 = time.process_time()
        mujoco.mj_step(model, data, nstep=per_sample)
        cpu += time.process_time() - t0
        omega.append([float(x) for x in data.qvel[3:6]])
    return {"integrator": integrator, "dt": dt, "cpu_s": cpu, "omega": omega}


def main():
    for dt in (float(a) for a in sys.argv[1:]):
        for integrator in ("Euler", "implicitfast", "RK4"):
            print(json.dumps(run(integrator, dt)), flush=True)


if __name__ == "__main__":
    main()
