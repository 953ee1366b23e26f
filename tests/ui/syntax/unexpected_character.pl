block(café).
