import rotorlib

print(rotorlib.orbit("pendulum", 3.9).trace)  # 1. tr M of the librational pendulum
print(rotorlib.orbit("pendulum", "3.9", digits=40).trace_str)  # ... to 40 digits
o = rotorlib.orbit("IS^l_2", 3.999)  # 2. a newborn orbit and its multipliers
print(o.period, o.multipliers, o.stability)
b = rotorlib.family("IS^l_1", (4.0, 4.2))  # 3. a family's period against E
print(list(zip(b.E, b.period)), b.reason)
a = rotorlib.census(4.3, 8.0)  # 4. the stable orbits of a census
print([(x.label, x.period) for x in a.orbits if x.stability == "stable"])
print(rotorlib.transition("IS^l_2", digits=20).E_str)  # 5. a transition energy
