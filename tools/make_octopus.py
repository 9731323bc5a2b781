# Writes crates/splineskin/assets/octopus.svg, the octopus drawn for splineskin (top view: a round
# mantle and eight wavy tapering arms). The outline is a closed Catmull-Rom spline through points
# along the arms, written as cubic Beziers (so its junctions are smooth); run: python3 tools/make_octopus.py
import math
import os
CX, CY = 320.0, 300.0
R = 78.0          # mantle radius
L = 190.0         # arm length from the rim
ARMS = 8
def arm_frame(k):
    th = 2*math.pi*k/ARMS - math.pi/2 + math.pi/ARMS
    return th
def centre(k, s):
    """Centre line of arm k at s in [0,1] (0 at the rim), a gentle S wave."""
    th = arm_frame(k)
    r = R*1.02 + L*s
    bend = 0.32*math.sin(math.pi*s*1.2 + k*0.9)*s   # radians of sideways swing
    a = th + bend*0.55
    return (CX + r*math.cos(a), CY + r*math.sin(a))
def width(s):
    return 25.0*(1-s) + 6.5*s
def normal(k, s):
    e = 1e-4
    p0 = centre(k, max(0, s-e)); p1 = centre(k, min(1, s+e))
    dx, dy = p1[0]-p0[0], p1[1]-p0[1]; n = math.hypot(dx, dy)
    return (-dy/n, dx/n), (dx/n, dy/n)
pts = []
for k in range(ARMS):
    th = arm_frame(k)
    ss = [0.0, 0.18, 0.38, 0.58, 0.78, 0.93]
    # right side out (one side), tip, left side back
    side_a = []; side_b = []
    for s in ss:
        c = centre(k, s); (nx, ny), _ = normal(k, s); w = width(s)
        side_a.append((c[0]-nx*w, c[1]-ny*w)); side_b.append((c[0]+nx*w, c[1]+ny*w))
    c = centre(k, 1.0); _, (tx, ty) = normal(k, 1.0)
    tip = (c[0]+tx*7.0, c[1]+ty*7.0)
    pts += side_a + [tip] + side_b[::-1]
    # web between this arm and the next, on the mantle rim
    th2 = th + math.pi/ARMS
    pts.append((CX + R*0.97*math.cos(th2), CY + R*0.97*math.sin(th2)))
# orient: make counter-clockwise in y-up? just keep; closed Catmull-Rom
n = len(pts)
def f(v): return f"{v:.2f}".rstrip('0').rstrip('.')
d = f"M {f(pts[0][0])} {f(pts[0][1])}"
for i in range(n):
    p0, p1, p2, p3 = pts[i-1], pts[i], pts[(i+1)%n], pts[(i+2)%n]
    c1 = (p1[0]+(p2[0]-p0[0])/6, p1[1]+(p2[1]-p0[1])/6)
    c2 = (p2[0]-(p3[0]-p1[0])/6, p2[1]-(p3[1]-p1[1])/6)
    d += f" C {f(c1[0])} {f(c1[1])} {f(c2[0])} {f(c2[1])} {f(p2[0])} {f(p2[1])}"
d += " Z"
suckers = []
for k in range(ARMS):
    for s in (0.3, 0.5, 0.68, 0.84):
        c = centre(k, s); r = width(s)*0.42
        suckers.append(f'<circle cx="{f(c[0])}" cy="{f(c[1])}" r="{f(r)}"/>')
handles = [(CX, CY)] + [centre(k, 0.96) for k in range(ARMS)]
svg = f'''<svg xmlns="http://www.w3.org/2000/svg" width="640" height="600" viewBox="0 0 640 600">
  <title>splineskin example: an octopus</title>
  <defs>
    <radialGradient id="mantle" cx="0.42" cy="0.38" r="0.7">
      <stop offset="0" stop-color="#f3a6c8"/>
      <stop offset="1" stop-color="#b4457f"/>
    </radialGradient>
  </defs>
  <g id="octopus" stroke="#5a1d3d" stroke-width="3" stroke-linejoin="round" stroke-linecap="round">
    <path id="outline" fill="#c9578f" d="{d}"/>
    <g id="suckers" fill="#f7d3e4" stroke="#8e3563" stroke-width="1.5">
      {chr(10).join("      "+s for s in suckers).strip()}
    </g>
    <circle id="mantle-top" cx="{f(CX)}" cy="{f(CY)}" r="{f(R*0.8)}" fill="url(#mantle)" stroke-width="2.5"/>
    <ellipse id="eye-left" cx="{f(CX-24)}" cy="{f(CY-10)}" rx="14" ry="17" fill="#ffffff" stroke-width="2"/>
    <ellipse id="eye-right" cx="{f(CX+24)}" cy="{f(CY-10)}" rx="14" ry="17" fill="#ffffff" stroke-width="2"/>
    <circle id="pupil-left" cx="{f(CX-21)}" cy="{f(CY-6)}" r="6.5" fill="#2a0c1c" stroke="none"/>
    <circle id="pupil-right" cx="{f(CX+27)}" cy="{f(CY-6)}" r="6.5" fill="#2a0c1c" stroke="none"/>
    <path id="smile" fill="none" stroke-width="2.5" d="M {f(CX-14)} {f(CY+22)} C {f(CX-6)} {f(CY+31)} {f(CX+6)} {f(CY+31)} {f(CX+14)} {f(CY+22)}"/>
  </g>
</svg>
'''
open(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'crates', 'splineskin', 'assets', 'octopus.svg'), 'w').write(svg)
print("octopus handles (mantle centre, arm tips):", [(round(x, 1), round(y, 1)) for x, y in handles])

