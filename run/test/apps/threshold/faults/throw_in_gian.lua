-- A throw naming no component of the deployment.
return {
  { on = { time = 0.05 }, throw = "Gian" },
}
