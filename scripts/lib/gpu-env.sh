# scripts/lib/gpu-env.sh — sourced by scripts/gpu-check and scripts/gpu-probe
# on a machine with a GPU: points the libraries, the tests and the OpenCL ICD
# loader at an unpacked scripts/gpu-bundle.
#   gpu_env BUNDLE_DIR OUT_DIR   (after it: $pmc is the bundle's pmc)
#
# The OpenCL driver: $OCL_ICD_VENDORS when set; else the ICD files in
# /etc/OpenCL/vendors, plus NVIDIA's libnvidia-opencl.so.1 where the driver put
# it (the loader's cache, /usr/local/nvidia/lib64, /usr/lib/x86_64-linux-gnu,
# then anywhere under /usr, /lib or /opt), named in an ICD file of our own
# under OUT_DIR/icd. Messages go to stdout and to $log when it is set.
gpu_env() {
  local bundle=$1 out=$2 driver
  export LD_LIBRARY_PATH="$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export PMC_MTLX_LIBRARY=$bundle/mtlx-libraries PMC_SCENES=$bundle/scenes
  export PMC_TEST_BINARY_DIR=$bundle PMC_TEST_PMC=$bundle/bin/pmc
  pmc=$bundle/bin/pmc
  if [ -z "${OCL_ICD_VENDORS:-}" ] && ! grep -q -s nvidia /etc/OpenCL/vendors/*.icd; then
    driver=$( (ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so\.1/ {print $NF}'
               ls /usr/local/nvidia/lib64/libnvidia-opencl.so.1 /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 2>/dev/null
               find /usr /lib /opt -name 'libnvidia-opencl.so*' 2>/dev/null) | head -1)
    if [ -n "$driver" ]; then
      mkdir -p "$out/icd"
      cp /etc/OpenCL/vendors/*.icd "$out/icd/" 2>/dev/null
      echo "$driver" >"$out/icd/nvidia.icd"
      export OCL_ICD_VENDORS=$out/icd
      export LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$(dirname "$driver")"
      echo "gpu-env: OpenCL driver $driver (ICD file written to $out/icd)" | tee -a "${log:-/dev/null}"
    fi
  fi
}
