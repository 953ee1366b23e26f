config({arms: 2}).
