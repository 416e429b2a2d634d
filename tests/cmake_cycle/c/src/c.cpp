int c_symbol() { return 0; }
