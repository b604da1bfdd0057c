[exit 2]
examples/bonded_pair.toml:contact: the emitted kernel does not carry bond springs yet, so its step would exceed the scene's; dtcrit step gives the step of this scene
