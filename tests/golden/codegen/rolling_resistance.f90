[exit 2]
examples/rolling_resistance.toml:contact: the emitted kernel does not carry rotational springs or dashpots (kr, ktw, cr, ctw) yet, so its step would exceed the scene's; dtcrit step gives the step of this scene
